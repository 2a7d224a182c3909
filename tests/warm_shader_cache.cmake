# Compiles the pipelines the tests use into the Mesa shader cache the tests
# share (MESA_SHADER_CACHE_DIR, set on every test), so that each test pays
# only for its own work. A cold compile of the GI passes takes 15 s on
# lavapipe and one of the path tracer 25-30 s, and lavapipe compiles a
# variant of a shader for each kind of image bound to it: sampler state,
# format, and whether each side of the image is a power of two (a warm-up of
# one class shares nothing with another's). So ctest runs this once per
# class of image size (both sides powers of two, one, the other, neither),
# each a setup of the fixture "shader_cache":
#   cmake -DBOUNCE=path/to/bounce -DSCRATCH=folder -DWIDTH=w -DHEIGHT=h -P warm_shader_cache.cmake
# On success it leaves the stamp warmed-WIDTHxHEIGHT in the cache folder
# (scripts/sanitize.sh looks for them to skip warming a warm cache again).
foreach(variable BOUNCE SCRATCH WIDTH HEIGHT)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "warm_shader_cache.cmake: pass -D${variable}=...")
  endif()
endforeach()
if(NOT DEFINED ENV{MESA_SHADER_CACHE_DIR})
  message(FATAL_ERROR "warm_shader_cache.cmake: set MESA_SHADER_CACHE_DIR to the cache the tests share")
endif()
# A folder of this run's own under SCRATCH: no other process, another
# warm-up of the same class included (a second ctest in the same build tree,
# or one left running by an interrupted run), writes into it or removes it
# while this one renders there.
string(RANDOM LENGTH 12 token)
set(OUT "${SCRATCH}/warm-${WIDTH}x${HEIGHT}-${token}")
file(MAKE_DIRECTORY "${OUT}")

# One command per entry, its arguments separated by "|" (a CMake list would
# flatten them all into one).
set(size "--width|${WIDTH}|--height|${HEIGHT}")
set(commands
  # An environment map for the commands below (2:1, as maps must be).
  "render|cornell|--width|32|--height|16|--gi|off|--out|${OUT}/map"
  # G-buffer, direct light, sky, every GI pass and its reservoir views.
  "render|cornell|${size}|--frames|2|--gi-warmup|1|--dump-stages|--out|${OUT}/render"
  # The same under an environment map, and with no light at all.
  "render|cornell|${size}|--frames|2|--gi-warmup|1|--env|${OUT}/map/render.exr|--no-sun|--out|${OUT}/lit-by-map"
  "render|cornell|${size}|--gi-warmup|1|--no-sun|--out|${OUT}/dark"
  # The path tracer and its resolve, under the sky and under a map (a
  # variant of its own, 28 s, which the tests of scenes with a sky use).
  "reference|cornell|${size}|--spp|1|--out|${OUT}/reference/sky.exr"
  "reference|cornell|${size}|--spp|1|--env|${OUT}/map/render.exr|--out|${OUT}/reference/map.exr"
  # The denoiser, on the path tracer's signals handed over as an engine's own.
  "denoise|cornell|${size}|--frames|2|--reference-spp|1|--dump-stages|--out|${OUT}/denoise"
  # BVH ray throughput and the copy-bandwidth probe.
  "bench|cornell|${size}|--frames|1|--warmup|0|--rays|64|--copy-mb|1")
foreach(command IN LISTS commands)
  string(REPLACE "|" ";" arguments "${command}")
  string(REPLACE "|" " " shown "${command}")
  execute_process(COMMAND "${BOUNCE}" ${arguments} RESULT_VARIABLE status OUTPUT_QUIET ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    file(REMOVE_RECURSE "${OUT}")
    message(FATAL_ERROR "bounce ${shown} failed (${status}): ${errors}")
  endif()
  message(STATUS "warmed: bounce ${shown}")
endforeach()
file(REMOVE_RECURSE "${OUT}")
file(TOUCH "$ENV{MESA_SHADER_CACHE_DIR}/warmed-${WIDTH}x${HEIGHT}")
