// CONSTANT_BLOCK: the storage of a pass's constant block, so that
//   layout(set = 0, binding = 0, std140) CONSTANT_BLOCK FrameBlock { ... } gIn_Frame;
// is a uniform block on GPUs and a read-only storage buffer in the variant
// compiled for CPU drivers (BOUNCE_CONSTANTS_IN_STORAGE_BUFFERS; the host
// picks it, gpu::Context::constantsInStorageBuffers). lavapipe specialises a
// shader on the uniform-block values that steer its control flow (image
// sizes, settings: it inlines them), compiling 20-25 s for every new set of
// values of the larger passes; storage buffers it does not specialise on.
// On GPUs uniform blocks are faster (7 % over the GI's diffuse branch on an
// H100), so each build keeps what suits its device.
#ifndef BOUNCE_CONSTANT_BLOCK_GLSL
#define BOUNCE_CONSTANT_BLOCK_GLSL

#ifdef BOUNCE_CONSTANTS_IN_STORAGE_BUFFERS
#define CONSTANT_BLOCK restrict readonly buffer
#else
#define CONSTANT_BLOCK uniform
#endif

#endif
