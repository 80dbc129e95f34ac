// A library that behaves, for LeakSanitizer, like Mesa 22.3's lavapipe driver (libvulkan_lvp.so)
// did on AMD Zen CPUs (tests/sanitizers/lsan.supp): a one-time initialiser (pthread_once) keeps a
// 128-byte realloc'd block in the library's own globals and never frees it. Built like Debian's
// Mesa: not instrumented, no frame pointers. While the library is loaded the block is reachable;
// once it is dlclose'd the pointer is gone with the library's data, and LeakSanitizer reports a
// direct leak whose innermost frames lie in a module no longer mapped.
#include <pthread.h>

#include <cstdlib>

namespace {

void* kept_block = nullptr;
pthread_once_t kept_block_once = PTHREAD_ONCE_INIT;

void allocate_kept_block() {
  kept_block = std::realloc(kept_block, 128);
  if (kept_block) static_cast<volatile char*>(kept_block)[0] = 1;
}

}  // namespace

extern "C" void once_module_initialise() { pthread_once(&kept_block_once, allocate_kept_block); }
