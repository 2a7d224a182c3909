# Compiles every pipeline the tests use once, into the Mesa shader cache the
# tests share (MESA_SHADER_CACHE_DIR, set on every test). On lavapipe a cold
# compile of the GI passes or the path tracer takes 20-25 s per process;
# with the cache warm, each test pays only for its own work.
# Run by ctest as the setup of the fixture "shader_cache":
#   cmake -DBOUNCE=path/to/bounce -DOUT=scratch/folder -P warm_shader_cache.cmake
foreach(variable BOUNCE OUT)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "warm_shader_cache.cmake: pass -D${variable}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${OUT}")

# One command per entry, its arguments separated by "|" (a CMake list would
# flatten them all into one).
# lavapipe compiles a variant of a shader for each kind of sampler state and
# image format bound to it, so the environment is warmed both as the
# procedural sky and as a map (the first render's image, 2:1).
set(commands
  # G-buffer, direct light, sky, every GI pass and its reservoir views.
  "render|cornell|--width|32|--height|16|--frames|2|--gi-warmup|1|--dump-stages|--out|${OUT}/render"
  # The same with an environment map, and with no light at all.
  "render|cornell|--width|16|--height|16|--frames|2|--gi-warmup|1|--env|${OUT}/render/render.exr|--no-sun|--out|${OUT}/map"
  "render|cornell|--width|16|--height|16|--gi-warmup|1|--no-sun|--out|${OUT}/dark"
  # The path tracer and its resolve, under the sky and under a map.
  "reference|cornell|--width|8|--height|8|--spp|1|--out|${OUT}/reference/ref.exr"
  "reference|cornell|--width|8|--height|8|--spp|1|--env|${OUT}/render/render.exr|--out|${OUT}/reference/map.exr"
  # BVH ray throughput and the copy-bandwidth probe.
  "bench|cornell|--width|8|--height|8|--frames|1|--warmup|0|--rays|64|--copy-mb|1")
foreach(command IN LISTS commands)
  string(REPLACE "|" ";" arguments "${command}")
  string(REPLACE "|" " " shown "${command}")
  execute_process(COMMAND "${BOUNCE}" ${arguments} RESULT_VARIABLE status OUTPUT_QUIET ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "bounce ${shown} failed (${status}): ${errors}")
  endif()
  message(STATUS "warmed: bounce ${shown}")
endforeach()
file(REMOVE_RECURSE "${OUT}")
