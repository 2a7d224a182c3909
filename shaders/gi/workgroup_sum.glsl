// A vec4 summed over every invocation of a workgroup in a fixed order (a
// tree in shared memory): the same bits every run, where atomics would add
// in whichever order the threads come. The including shader defines
// WORKGROUP_SUM_LANES, its invocations a workgroup (a power of two).
#ifndef BOUNCE_GI_WORKGROUP_SUM_GLSL
#define BOUNCE_GI_WORKGROUP_SUM_GLSL

#ifndef WORKGROUP_SUM_LANES
#error "define WORKGROUP_SUM_LANES (the workgroup's invocations, a power of two) first"
#endif

shared vec4 gWorkgroupSums[WORKGROUP_SUM_LANES];

// Every invocation of the workgroup calls it (it waits at barriers) with
// its own `value`; each gets the workgroup's sum.
vec4 workgroupSum(vec4 value) {
  uint lane = gl_LocalInvocationIndex;
  gWorkgroupSums[lane] = value;
  barrier();
  for (uint width = uint(WORKGROUP_SUM_LANES) / 2u; width > 0u; width /= 2u) {
    if (lane < width) gWorkgroupSums[lane] += gWorkgroupSums[lane + width];
    barrier();
  }
  return gWorkgroupSums[0];
}

#endif
