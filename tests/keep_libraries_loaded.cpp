// Preloaded into the tests of the sanitizer job (scripts/sanitize.sh) only:
// dlclose() leaves every library mapped. The Vulkan loader unloads the
// driver (lavapipe, and LLVM with it) when the instance is destroyed; a leak
// inside them is reported at exit, when LeakSanitizer could then no longer
// name their library, and the suppressions in sanitizer-suppressions.txt
// match driver leaks by library name.
extern "C" int dlclose(void*) { return 0; }
