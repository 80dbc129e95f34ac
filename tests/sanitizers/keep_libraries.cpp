// An LD_PRELOAD library for the asan test preset (CMakePresets.json): dlclose does nothing, so
// every library a process loads stays mapped until it exits. LeakSanitizer then sees a block that
// a library keeps in its own globals as reachable, as it is, instead of as a leak whose stack it
// cannot name: Mesa 25's lavapipe on AMD Zen CPUs keeps such a block (u_cpu_detect.c's L3
// affinity masks, allocated once per process) and the Vulkan loader unloads the driver at
// vkDestroyInstance (tests/sanitizers/once_module.cpp reproduces the pattern on any CPU). A block
// nothing points to is still reported, and with its frames named, since its library is mapped.
// Not instrumented. ASan's own dlclose interceptor, in the executable, calls this one.
extern "C" int dlclose(void* /*handle*/) { return 0; }
