// A program that leaks on purpose, for the sanitizer build's own checks (sanitizer_test.cpp):
//   leak_probe lost-block          loses a block allocated in leak_probe_lost_block();
//   leak_probe unloaded-module LIB loads LIB (once_module.c), runs its one-time initialiser and
//                                  unloads it again, as the Vulkan loader loads and unloads the
//                                  driver around an instance.
// Under the asan preset both must end in a LeakSanitizer report; what the report names is what
// the tests check.
#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

// Volatile so the optimiser cannot drop the allocation: the block is reachable from nothing.
void* volatile g_sink = nullptr;

[[gnu::noinline]] void leak_probe_lost_block() {
  g_sink = std::malloc(48);
  g_sink = nullptr;
}

[[gnu::noinline]] int leak_probe_load_and_unload(const char* library) {
  void* handle = ::dlopen(library, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    std::fprintf(stderr, "leak_probe: %s\n", ::dlerror());
    return 2;
  }
  auto* initialise = reinterpret_cast<void (*)()>(::dlsym(handle, "once_module_initialise"));
  if (!initialise) {
    std::fprintf(stderr, "leak_probe: %s has no once_module_initialise\n", library);
    return 2;
  }
  initialise();
  return ::dlclose(handle) == 0 ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "lost-block") == 0) {
    leak_probe_lost_block();
    return 0;
  }
  if (argc == 3 && std::strcmp(argv[1], "unloaded-module") == 0)
    return leak_probe_load_and_unload(argv[2]);
  std::fprintf(stderr, "usage: leak_probe lost-block | unloaded-module LIBRARY\n");
  return 2;
}
