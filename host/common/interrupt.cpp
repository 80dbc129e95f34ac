// The signal handlers of interrupt.h: async-signal-safe (a sig_atomic_t, unlink, _exit).
#include "common/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace hrpp {
namespace {

volatile std::sig_atomic_t g_signal = 0;
char g_writing[4096] = {0};
std::atomic<bool> g_has_writing{false};
struct sigaction g_old_int, g_old_term;

extern "C" void on_signal(int sig) {
  if (g_signal != 0) {  // the second: nothing half-written stays
    if (g_has_writing.load()) ::unlink(g_writing);
    ::_exit(128 + sig);
  }
  g_signal = sig;
}

}  // namespace

InterruptScope::InterruptScope() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

InterruptScope::~InterruptScope() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
}

int interrupt_signal() { return g_signal; }

void set_file_being_written(const char* path) {
  g_has_writing.store(false);
  if (path == nullptr) return;
  std::strncpy(g_writing, path, sizeof(g_writing) - 1);
  g_writing[sizeof(g_writing) - 1] = '\0';
  g_has_writing.store(true);
}

}  // namespace hrpp
