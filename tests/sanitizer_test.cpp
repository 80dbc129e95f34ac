// The sanitizer build's own checks (asan preset only): LeakSanitizer reports name functions, so
// a suppression can match (llvm-symbolizer found, tools/setup.sh); a leak whose allocating
// library was unloaded before exit, as the Vulkan loader unloads the driver, is reported with the
// frames still mapped when unwound in full (how an entry in tests/sanitizers/lsan.supp would
// match one); and Vulkan under ASan gives the same verdict on the CPU paths lavapipe takes on
// other machines.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_runner.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

// `ENV PROGRAM ARGS` under the test's environment (the asan preset's), with stdin from /dev/null.
test::CliResult run_with_env(const std::string& env, const std::string& program,
                             const std::string& args, const fs::path& dir) {
  return test::run_command(env + " " + program + " " + args, dir);
}

// The preset's LSAN_OPTIONS followed by `extra` (a later flag overrides an earlier one).
std::string lsan_options(const std::string& extra) {
  const char* preset = std::getenv("LSAN_OPTIONS");
  return "LSAN_OPTIONS='" + std::string(preset ? preset : "") + ":" + extra + "'";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class SanitizerReport : public test::CliTest {
 protected:
  // leak_probe ARGS; `env` goes first (e.g. "LD_PRELOAD=": without the preset's preload).
  test::CliResult probe(const std::string& args, const std::string& extra_lsan_options = "",
                        const std::string& env = "") {
    return run_with_env(env + " " + lsan_options(extra_lsan_options), HRPP_LEAK_PROBE, args, dir_);
  }
};

// A report must name the function that allocated the lost block; without a symbolizer the frame
// reads "(leak_probe+0x...)" and no suppression by function name could ever match.
TEST_F(SanitizerReport, NamesTheLeakingFunction) {
  const test::CliResult r = probe("lost-block");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("Direct leak of 48 byte(s) in 1 object(s)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in (anonymous namespace)::leak_probe_lost_block()"), std::string::npos)
      << r.err;
}

// Lavapipe's pattern: a one-time block kept in the globals of a library unloaded before exit.
// Unloaded, the block is reported and its own frames cannot be named; full unwinding
// (fast_unwind_on_malloc=0: the library has no frame pointers) reaches the mapped caller, which
// a suppression can name, and the preset keeps a used suppression silent. With the preset's
// preload (tests/sanitizers/keep_libraries.cpp) the library stays mapped and the block is
// reachable: nothing is reported.
TEST_F(SanitizerReport, LeakFromAnUnloadedLibraryNamesTheMappedCaller) {
  const std::string args = std::string("unloaded-module ") + HRPP_ONCE_MODULE;
  const std::string unloaded = "LD_PRELOAD=", full_unwind = "fast_unwind_on_malloc=0";
  const test::CliResult r = probe(args, full_unwind, unloaded);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("Direct leak of 128 byte(s) in 1 object(s)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("<unknown module>"), std::string::npos) << r.err;
  // (libc's frames between them are named only where its debug symbols are installed.)
  EXPECT_NE(r.err.find("leak_probe_load_and_unload("), std::string::npos) << r.err;

  const fs::path supp = dir_ / "caller.supp";
  std::ofstream(supp) << "leak:leak_probe_load_and_unload\n";
  const std::string suppress = full_unwind + ":suppressions=" + supp.string();
  const test::CliResult suppressed = probe(args, suppress, unloaded);
  EXPECT_EQ(suppressed.status, 0) << suppressed.err;
  // print_suppressions=0: LeakSanitizer's table of used suppressions on stderr would break every
  // test that counts a refusal's one line there.
  EXPECT_EQ(suppressed.err, "");
  const test::CliResult listed = probe(args, suppress + ":print_suppressions=1", unloaded);
  EXPECT_EQ(listed.status, 0) << listed.err;
  EXPECT_NE(listed.err.find("Suppressions used:"), std::string::npos) << listed.err;
  EXPECT_NE(listed.err.find("leak_probe_load_and_unload"), std::string::npos) << listed.err;

  const test::CliResult kept = probe(args);  // the preset's options and preload
  EXPECT_EQ(kept.status, 0) << kept.err;
  EXPECT_EQ(kept.err, "");
}

// The project's suppression file is the one the preset passes, and it loads (a malformed file
// makes every sanitized process die at start-up, so this also guards every other test).
TEST_F(SanitizerReport, PresetPassesTheProjectSuppressions) {
  const char* lsan = std::getenv("LSAN_OPTIONS");
  ASSERT_NE(lsan, nullptr);
  const fs::path supp = fs::path(HRPP_TEST_DATA_DIR).parent_path() / "sanitizers" / "lsan.supp";
  EXPECT_NE(std::string(lsan).find("suppressions=" + supp.string()), std::string::npos) << lsan;
  const char* preload = std::getenv("LD_PRELOAD");
  ASSERT_NE(preload, nullptr);
  EXPECT_TRUE(fs::exists(preload)) << preload;
  // A block nothing points to is reported under the preload too.
  const test::CliResult r = probe("lost-block");
  EXPECT_EQ(r.err.find("Could not"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("leak_probe_lost_block"), std::string::npos) << r.err;
}

// The check that failed on AMD CPUs only (BadInputCli.ScenesOverTheDeviceMemoryAreRefused-
// BeforeUpload): hrpp refusing a scene after creating its Vulkan instance, under ASan, must give
// the refusal tests' verdict (exit 1, exactly one line on stderr) on every CPU path lavapipe
// takes: this CPU's own, and where CPUID faulting lets tests/sanitizers/cpuid_override.cpp fake
// them, an AMD Zen CPU's (family17h: Mesa walks the Zen L3 topology and keeps a block that
// tests/sanitizers/keep_libraries.cpp leaves reachable) and one without AVX-512. A path is told
// by a second run with GALLIUM_DUMP_CPU (whose lines would break the one-line check, so the
// verdict run goes without it).
struct CpuPath {
  std::string name;  // CPUID_OVERRIDE's value; empty: this CPU as it is
  std::string env;   // the variables that select it
  bool zen = false;  // Mesa walked the AMD Zen L3 topology
};

std::string refusal_args(const fs::path& dir) {
  return "render builtin:cornell --size 512x512 --spp 1 --out " + (dir / "i.exr").string();
}
const std::string kHeapCap = "HRPP_DEVICE_HEAP_MIB=1";

// The CPU paths this machine can run; `missing` collects the ones it cannot fake, with why.
std::vector<CpuPath> runnable_cpu_paths(const fs::path& dir, std::string& missing) {
  std::vector<CpuPath> paths;
  for (const std::string mode : {"", "family17h", "no-avx512", "family17h,no-avx512"}) {
    CpuPath path{mode, kHeapCap};
    if (!mode.empty())
      path.env += " CPUID_OVERRIDE=" + mode + " LD_PRELOAD=" + HRPP_CPUID_OVERRIDE;
    const test::CliResult dump =
        run_with_env(path.env + " GALLIUM_DUMP_CPU=true", HRPP_BINARY, refusal_args(dir), dir);
    if (contains(dump.err, "cpuid_override: unavailable")) {
      missing += " " + mode;
      continue;
    }
    path.zen = contains(dump.err, "CPU <-> L3 cache mapping");
    if (contains(mode, "family17h")) {
      EXPECT_TRUE(contains(dump.out, "util_cpu_caps.x86_cpu_type = 23")) << dump.out;
      EXPECT_TRUE(path.zen) << dump.err;
    }
    if (contains(mode, "no-avx512")) EXPECT_TRUE(contains(dump.out, "has_avx512f = 0")) << dump.out;
    paths.push_back(path);
  }
  return paths;
}

TEST_F(SanitizerReport, VulkanUnderAsanGivesOneVerdictOnEveryCpuPath) {
  std::string missing;
  const std::vector<CpuPath> paths = runnable_cpu_paths(dir_, missing);
  bool zen = false;
  for (const CpuPath& path : paths) {
    SCOPED_TRACE("CPUID_OVERRIDE=" + path.name);
    const test::CliResult r = run_with_env(path.env, HRPP_BINARY, refusal_args(dir_), dir_);
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(contains(r.err, "more than the device's memory heap as capped by")) << r.err;
    zen = zen || path.zen;
  }
  std::printf("CPU paths run: this CPU's own (%s)%s\n",
              paths.front().zen ? "AMD Zen" : "not AMD Zen",
              missing.empty() ? ", and every faked one"
                              : (", not run (no CPUID faulting):" + missing).c_str());
  if (!zen) GTEST_SKIP() << "the AMD Zen path was not run: this CPU is no Zen and cannot fake one";
}

}  // namespace
}  // namespace hrpp
