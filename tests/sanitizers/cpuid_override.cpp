// An LD_PRELOAD library that changes what the CPUID instruction reports, so that one machine can
// run the code paths that Mesa's lavapipe takes on other CPUs (tests/sanitizer_test.cpp):
//   CPUID_OVERRIDE=family17h   leaf 1 reports x86 family 0x17 (AMD Zen 1/2, which Mesa 22.3's
//                              util_cpu_detect() recognises by the family alone) and leaf
//                              0x8000001D:3 an L3 cache shared by every CPU, so Mesa walks the
//                              Zen L3 topology as it does on an AMD EPYC;
//   CPUID_OVERRIDE=no-avx512   leaf 7 reports no AVX-512 (Mesa and LLVM then generate AVX2 code);
// both together with a comma. It uses Linux's CPUID faulting (arch_prctl ARCH_SET_CPUID, Intel
// CPUs that have it): every CPUID then traps with SIGSEGV; the handler runs the real instruction
// with faulting briefly off, edits the answer and steps over it. Where CPUID faulting is missing
// it prints "cpuid_override: unavailable" and changes nothing; where it works it prints nothing
// (the tests count the lines a refusal writes to stderr). Not instrumented, and only for
// tests: it reports the real CPU's features otherwise, so code runs as on that CPU.
#include <asm/prctl.h>
#include <cpuid.h>
#include <signal.h>
#include <sys/syscall.h>
#include <ucontext.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

bool g_family17h = false;
bool g_no_avx512 = false;
struct sigaction g_previous {};

long set_cpuid_enabled(bool enabled) { return ::syscall(SYS_arch_prctl, ARCH_SET_CPUID, enabled); }

void edit(uint32_t leaf, uint32_t subleaf, uint32_t r[4]) {
  if (g_family17h && leaf == 1) {
    r[0] = (r[0] & 0xF000000Fu) | (0x8u << 20) | (0x3u << 16) | (0xFu << 8) | (0x1u << 4);
  } else if (g_family17h && leaf == 0x8000001Du && subleaf == 3) {
    const uint32_t sharing = static_cast<uint32_t>(::sysconf(_SC_NPROCESSORS_CONF));
    r[0] = 3u | (3u << 5) | (1u << 8) | ((sharing - 1u) << 14);  // unified, level 3
    r[1] = r[2] = r[3] = 0;
  } else if (g_no_avx512 && leaf == 7 && subleaf == 0) {
    r[1] &= ~((1u << 16) | (1u << 17) | (1u << 21) | (1u << 26) | (1u << 27) | (1u << 28) |
              (1u << 30) | (1u << 31));
    r[2] &= ~((1u << 1) | (1u << 6) | (1u << 11) | (1u << 12) | (1u << 14));
    r[3] &= ~((1u << 2) | (1u << 3) | (1u << 8) | (1u << 23));
  } else if (g_no_avx512 && leaf == 7 && subleaf == 1) {
    r[0] &= ~(1u << 5);
  }
}

void on_segv(int sig, siginfo_t* info, void* context) {
  auto* uc = static_cast<ucontext_t*>(context);
  greg_t* g = uc->uc_mcontext.gregs;
  const auto* pc = reinterpret_cast<const unsigned char*>(g[REG_RIP]);
  if (pc[0] != 0x0F || pc[1] != 0xA2) {  // not CPUID: whoever handled SIGSEGV before us
    if (g_previous.sa_flags & SA_SIGINFO) return g_previous.sa_sigaction(sig, info, context);
    ::sigaction(SIGSEGV, &g_previous, nullptr);
    return;  // the faulting instruction runs again and now meets the previous disposition
  }
  const auto leaf = static_cast<uint32_t>(g[REG_RAX]), subleaf = static_cast<uint32_t>(g[REG_RCX]);
  uint32_t r[4];
  set_cpuid_enabled(true);
  __cpuid_count(leaf, subleaf, r[0], r[1], r[2], r[3]);
  set_cpuid_enabled(false);
  edit(leaf, subleaf, r);
  g[REG_RAX] = r[0];
  g[REG_RBX] = r[1];
  g[REG_RCX] = r[2];
  g[REG_RDX] = r[3];
  g[REG_RIP] += 2;
}

[[gnu::constructor]] void install() {
  const char* mode = std::getenv("CPUID_OVERRIDE");
  if (!mode || !*mode) return;
  g_family17h = std::strstr(mode, "family17h") != nullptr;
  g_no_avx512 = std::strstr(mode, "no-avx512") != nullptr;
  struct sigaction sa {};
  sa.sa_sigaction = on_segv;
  sa.sa_flags = SA_SIGINFO | SA_NODEFER;
  sigemptyset(&sa.sa_mask);
  if (::sigaction(SIGSEGV, &sa, &g_previous) != 0 || set_cpuid_enabled(false) != 0) {
    ::sigaction(SIGSEGV, &g_previous, nullptr);
    std::fprintf(stderr, "cpuid_override: unavailable (no CPUID faulting on this CPU)\n");
    return;
  }
}

}  // namespace
