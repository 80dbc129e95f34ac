// The HRPP flags and settings files of `hrpp trace` and `hrpp bench` as a user meets them: exact and hit-any
// prediction write the same hits file as --hrpp off; speculative mode reports its wrong closest
// hits; --stats JSON holds the configuration and counters that add up; bad values end in one
// line naming the flag and exit status 1.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "hrpp/predictor_stats.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
using test::read_file;

class HrppCli : public test::CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    // 64×64 primary rays of the teapot scene, each twice (the second finds the table warm).
    const Scene scene = load_scene(std::string(HRPP_TEST_SCENES_DIR) + "/teapot.scene.json");
    std::vector<gpu::Ray> rays = make_primary_rays(scene.cameras[0], 64, 64, false, 1);
    const std::vector<gpu::Ray> again = rays;
    rays.insert(rays.end(), again.begin(), again.end());
    rays_ = dir_ / "rays.bin";
    std::ofstream(rays_, std::ios::binary)
        .write(reinterpret_cast<const char*>(rays.data()),
               static_cast<std::streamsize>(rays.size() * sizeof(gpu::Ray)));
  }
  // `json` in the file NAME.json of the test's folder: --hrpp-config and its path.
  std::string settings(const std::string& json, const std::string& name) const {
    const fs::path file = dir_ / (name + ".json");
    std::ofstream(file) << json;
    return "--hrpp-config " + file.string();
  }
  // Traces the rays file; returns the hits file's bytes.
  std::string trace(const std::string& flags, const std::string& name) const {
    const fs::path hits = dir_ / (name + ".bin");
    const Result r = run("trace " + std::string(HRPP_TEST_SCENES_DIR) + "/teapot.scene.json --rays " +
                         rays_.string() + " --hits " + hits.string() + " " + flags);
    EXPECT_EQ(r.status, 0) << flags << "\n" << r.err;
    return read_file(hits);
  }

  fs::path rays_;
};

TEST_F(HrppCli, ExactAndAnyHitWriteTheHitsOfHrppOff) {
  const std::string off = trace("--hrpp off", "off");
  ASSERT_EQ(off.size(), 2u * 64 * 64 * 16);
  EXPECT_EQ(trace("--hrpp on --hrpp-mode exact", "exact"), off);
  EXPECT_EQ(trace("--hrpp on --hrpp-mode exact --table-preset tiny", "exact_tiny"), off);
  const std::string grid = R"({"hash": "grid-spherical", "hash_bits": 5, "go_up": 2})";
  const std::string every_grid =
      R"("keys": {"camera": )" + grid + R"(, "bounce": )" + grid + R"(, "shadow": )" + grid + "}";
  EXPECT_EQ(trace("--hrpp on --hrpp-mode exact " + settings("{" + every_grid + "}", "grid"),
                  "exact_grid"),
            off);
  EXPECT_EQ(trace("--hrpp on --hrpp-mode exact " +
                      settings(R"({"fallback": "root", )" + every_grid + "}", "grid_root"),
                  "exact_grid_root"),
            off);
  const std::string any_off = trace("--any-hit", "any_off");
  const std::string two = R"({"hash": "two-point", "hash_bits": 4})";
  EXPECT_EQ(trace("--any-hit --hrpp on " +
                      settings(R"({"keys": {"camera": )" + two + R"(, "bounce": )" + two +
                                   R"(, "shadow": )" + two + "}}",
                               "two"),
                  "any_on"),
            any_off);
  // Per-class keys: a light-space key with go-up subtrees for the shadow rays.
  EXPECT_EQ(trace("--any-hit --hrpp on " +
                      settings(R"({"keys": {"camera": {"hash": "grid-spherical"}, )"
                               R"("shadow": {"hash": "light-depth", "hash_bits": 4, "go_up": 3}}})",
                               "light"),
                  "any_light"),
            any_off);
  // --hrpp-rays any leaves closest-hit queries alone (no predictor line).
  const fs::path hits = dir_ / "rays_any.bin";
  const Result r = run("trace " + std::string(HRPP_TEST_SCENES_DIR) + "/teapot.scene.json --rays " +
                       rays_.string() + " --hits " + hits.string() + " --hrpp on --hrpp-rays any");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("hrpp        off"), std::string::npos) << r.out;
}

TEST_F(HrppCli, StatsJsonCountersAddUp) {
  const fs::path stats = dir_ / "stats.json";
  // Precision 4: neighbouring camera rays share keys, so the pilot rays' entries serve the rest.
  trace("--hrpp on --stats " + stats.string() + " " +
            settings(R"({"keys": {"camera": {"hash_bits": 4}, "bounce": {"hash_bits": 4}, )"
                     R"("shadow": {"hash_bits": 4}}})",
                     "bits4"),
        "spec");
  const nlohmann::json j = nlohmann::json::parse(read_file(stats));
  const nlohmann::json& h = j.at("hrpp");
  EXPECT_EQ(h.at("enabled"), true);
  EXPECT_EQ(h.at("keys").at("camera").at("hash"), "hrpp");
  EXPECT_EQ(h.at("keys").at("camera").at("hash_bits"), 4u);
  EXPECT_EQ(h.at("mode"), "speculative");
  // The defaults: the tuned preset for camera rays, the beam preset for shadow rays.
  EXPECT_EQ(h.at("keys").at("camera").at("table_bytes"), 16384u * 2 * (8 + 4 + 4 * 1));
  EXPECT_EQ(h.at("keys").at("shadow").at("table_bytes"), 4096u * 2 * (8 + 4 + 4 * 4));
  const nlohmann::json& s = h.at("summary");
  EXPECT_EQ(s.at("probes"), 2u * 64 * 64);
  EXPECT_EQ(s.at("predictor_hits").get<std::uint64_t>() + s.at("negatives").get<std::uint64_t>(),
            s.at("probes").get<std::uint64_t>());
  EXPECT_EQ(s.at("true_positives").get<std::uint64_t>() +
                s.at("false_positives").get<std::uint64_t>(),
            s.at("predictor_hits").get<std::uint64_t>());
  EXPECT_GT(s.at("true_positives").get<std::uint64_t>(), 0u);
  EXPECT_GT(s.at("savings").get<double>(), 0.0);  // true positives skip traversal
  EXPECT_LE(s.at("wrong_closest").get<std::uint64_t>(), s.at("true_positives").get<std::uint64_t>());
  // Every counter of the one list (HRPP_PREDICTOR_COUNTERS) under its key.
  for (const CounterKey& k : kPredictorCounterKeys) EXPECT_TRUE(s.contains(k.key)) << k.key;
  // The device and its driver (lavapipe: "llvmpipe Mesa ...").
  EXPECT_FALSE(j.at("device").at("name").get<std::string>().empty());
  EXPECT_FALSE(j.at("device").at("driver").get<std::string>().empty());
}

// Keys per ray class (--hrpp-config's keys.<class>) and --table-preset's "V" for every class or
// "class=V" for one, in order; the stats JSON has every class's key, and the flat fields in the
// "class=V" form.
TEST_F(HrppCli, KeysPerRayClass) {
  const fs::path stats = dir_ / "keys.json";
  trace("--hrpp on --table-preset tuned,shadow=beam --stats " + stats.string() + " " +
            settings(R"({"keys": {"camera": {"hash": "two-point", "hash_bits": 5}, )"
                     R"("bounce": {"hash": "two-point", "hash_bits": 5}, )"
                     R"("shadow": {"hash": "light", "hash_bits": 3, "go_up": 4}}})",
                     "per_class"),
        "keys");
  const nlohmann::json h = nlohmann::json::parse(read_file(stats)).at("hrpp");
  const nlohmann::json& k = h.at("keys");
  EXPECT_EQ(k.at("camera").at("hash"), "two-point");
  EXPECT_EQ(k.at("bounce").at("hash"), "two-point");
  EXPECT_EQ(k.at("shadow").at("hash"), "light");
  EXPECT_EQ(k.at("camera").at("hash_bits"), 5u);
  EXPECT_EQ(k.at("shadow").at("hash_bits"), 3u);
  EXPECT_EQ(k.at("camera").at("go_up"), 0u);
  EXPECT_EQ(k.at("shadow").at("go_up"), 4u);
  EXPECT_EQ(h.at("hash"), "camera=two-point,bounce=two-point,shadow=light");
  EXPECT_EQ(h.at("go_up"), "camera=0,bounce=0,shadow=4");
  EXPECT_EQ(h.at("table_nodes"), "camera=1,bounce=1,shadow=4");
  const Result help = run("trace --help");
  EXPECT_NE(help.out.find("class=V"), std::string::npos) << help.out;
  EXPECT_EQ(help.status, 0);
}

TEST_F(HrppCli, BadValuesNameTheFlag) {
  const std::string base = "trace --rays " + rays_.string() + " --hits " + (dir_ / "h.bin").string();
  for (const auto& [flags, needle] : std::vector<std::pair<std::string, std::string>>{
           {"--hrpp maybe", "--hrpp"},
           {"--hrpp on --hrpp-mode fast", "--hrpp-mode"},
           {"--hrpp on --table-preset shadow=huge", "--table-preset"},
           {"--hrpp on --table-preset huge", "--table-preset"},
           {"--hrpp on --table-preset sky=tuned", "--table-preset"},
           {"--hrpp on --hrpp-rays some", "--hrpp-rays"},
           {"--hrpp on --hash-bits 4", "--hash-bits"}}) {  // a setting of the file, not a flag
    const Result r = run(base + " " + flags);
    EXPECT_EQ(r.status, 1) << flags;
    EXPECT_NE(r.err.find(needle), std::string::npos) << flags << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << flags << ": " << r.err;
  }
}

// --hrpp-config: a run's --stats JSON re-runs its predictor (the same configuration in the new
// stats, the same hits and counters in the deterministic mode); a file setting one key equals
// the flag that sets it; flags given beside the file override it.
TEST_F(HrppCli, SettingsFileReRunsAStatsConfiguration) {
  const fs::path first = dir_ / "first.json", again = dir_ / "again.json";
  const std::string flags =
      "--hrpp on --table-preset small --hrpp-mode exact " +
      settings(R"({"batch": 64, "serial": true, "keys": {"camera": {"hash": "grid-spherical", )"
               R"("hash_bits": 5, "go_up": 1}, "bounce": {"hash_bits": 5, "go_up": 1}, )"
               R"("shadow": {"hash_bits": 5, "go_up": 1}}})",
               "deterministic");
  const std::string hits = trace(flags + " --stats " + first.string(), "first");
  EXPECT_EQ(trace("--hrpp-config " + first.string() + " --stats " + again.string(), "again"),
            hits);
  nlohmann::json a = nlohmann::json::parse(read_file(first)).at("hrpp");
  nlohmann::json b = nlohmann::json::parse(read_file(again)).at("hrpp");
  EXPECT_EQ(a, b);  // the configuration and, in batches, the counters too
  // One key in a file of its own against the flag.
  const fs::path one = dir_ / "one.json", by_flag = dir_ / "by_flag.json",
                 by_file = dir_ / "by_file.json";
  std::ofstream(one) << R"({"enabled": true, "keys": {"camera": {"table_preset": "small"}}})";
  trace("--hrpp on --table-preset camera=small --stats " + by_flag.string(), "by_flag");
  trace("--hrpp-config " + one.string() + " --stats " + by_file.string(), "by_file");
  a = nlohmann::json::parse(read_file(by_flag)).at("hrpp");
  b = nlohmann::json::parse(read_file(by_file)).at("hrpp");
  a.erase("summary");
  b.erase("summary");
  for (const char* k : {"answered_without_trace", "traced_with_shorter_tmax"}) {
    a.erase(k);
    b.erase(k);
  }
  EXPECT_EQ(a, b);
  // A flag beside the file wins.
  const fs::path over = dir_ / "over.json";
  trace("--hrpp-config " + one.string() + " --table-preset tiny --hrpp-mode exact --stats " +
            over.string(),
        "over");
  const nlohmann::json o = nlohmann::json::parse(read_file(over)).at("hrpp");
  EXPECT_EQ(o.at("keys").at("camera").at("table_sets"), 4u);  // tiny: 4 x 2 x 2
  EXPECT_EQ(o.at("mode"), "exact");
}

// Bad settings files end in one line naming the file and the key.
TEST_F(HrppCli, SettingsFileErrorsNameTheKey) {
  const std::string base = "trace --rays " + rays_.string() + " --hits " + (dir_ / "h.bin").string();
  const fs::path file = dir_ / "bad.json";
  for (const auto& [text, needle] : std::vector<std::pair<std::string, std::string>>{
           {R"({"enabled": true, "hash_bitz": 4})", "hash_bitz: unknown key"},
           {R"({"keys": {"camera": {"hash_bitz": 4}}})", "keys.camera.hash_bitz: unknown key"},
           {R"({"keys": {"sky": {"hash_bits": 4}}})", "keys.sky"},
           {R"({"keys": {"camera": {"hash_bits": 9}}})", "hash_bits"},
           {R"({"keys": {"camera": {"hash_bits": -1}}})", "keys.camera.hash_bits"},
           {R"({"keys": {"camera": {"hash": "md5"}}})", "keys.camera.hash"},
           {R"({"keys": {"camera": {"table_sets": 3}}})", "table_sets"},
           {R"({"mode": "fast"})", "mode"},
           {R"({"enabled": "yes"})", "enabled: must be true or false"},
           {R"({"ray_classes": ["sky"]})", "ray_classes"},
           {R"({"keys": {"shadow": {"gate": 0.5}}})", "keys.shadow.gate is 0.5"},  // no effect
           {R"({"hash_bits": 4})", "hash_bits is 4"},  // a summary that disagrees with "keys"
           {R"({"batch": 64, "pilot": 4})", "pilot is 4"},
           {R"({"keys": {"shadow": {"hash": "md5"}}})", "keys.shadow.hash"},
           {R"({"keys": {"camera": {"hash": "light"}}})", "hash"},  // shadow rays' key only
           {R"({"keys": {"shadow": {"hash_bits": 0}}})", "hash_bits"},
           {R"({"keys": {"bounce": {"go_up": 65}}})", "go_up"},
           {R"({"keys": {"shadow": {"go_up_size": 2}}})", "go_up_size"},
           {R"({"keys": {"shadow": {"go_up_size": "big"}}})", "keys.shadow.go_up_size"},
           {R"({"keys": {"bounce": {"table_policy": "mru"}}})", "keys.bounce.table_policy"},
           {R"({"batch": 100000})", "batch"},
           {R"({"keys": {"camera": {"hash_dir_bits": 3}}})", "hash_dir_bits"},  // the paper's key
           {R"({"keys": {"bounce": {"hash_dir_bits": 9}}})", "hash_dir_bits"},
           {R"({"keys": {"bounce": {"gate": -1}}})", "gate"},
           {R"({"keys": {"bounce": {"gate": "near"}}})", "keys.bounce.gate"},
           {R"({"mode": "exact", "keys": {"bounce": {"gate": 1.5}}})", "gate"},
           {"[1", "not JSON"},
           {"42", "must be a JSON object"}}) {
    std::ofstream(file) << text;
    const Result r = run(base + " --hrpp on --hrpp-config " + file.string());
    EXPECT_EQ(r.status, 1) << text;
    EXPECT_NE(r.err.find(file.string() + ": "), std::string::npos) << text << ": " << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << text << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << text << ": " << r.err;
  }
  const Result r = run(base + " --hrpp-config " + (dir_ / "none.json").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("none.json: cannot open"), std::string::npos) << r.err;
}

TEST_F(HrppCli, BenchPrintsPredictorFigures) {
  const fs::path json = dir_ / "bench.json";
  const Result r = run("bench teapot --rays 4096 --no-embree --repeat 1 --hrpp on --hrpp-mode exact "
                       "--json " + json.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("gpu-hrpp"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("savings"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(read_file(json));
  EXPECT_EQ(j.at("hrpp").at("mode"), "exact");
  EXPECT_EQ(j.at("total_mismatches"), 0);
  for (const auto& k : j.at("kinds")) EXPECT_TRUE(k.contains("hrpp")) << k.dump();
}

// bench has the shared options too: the validation layer (--validate, as on every GPU command;
// the rays checked against the CPU reference are --check-rays) and the BVH build.
TEST_F(HrppCli, BenchTakesTheSharedOptions) {
  const Result r = run("bench --rays 1024 --kinds primary --no-embree --repeat 1 "
                       "--validate --check-rays 512 --bvh-bins 8 --bvh-max-leaf 2 "
                       "--rays-per-invocation 4");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("Validation"), std::string::npos) << r.err;
}

// --save-rays: the batches as ray files (32 bytes a ray) and the triangle dump (36 bytes a
// triangle), for bench/embree_harness.cpp or `hrpp trace` to run on the same rays.
TEST_F(HrppCli, BenchSavesItsBatches) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "hrpp_bench_save_rays_test";
  std::filesystem::remove_all(dir);
  const Result r = run("bench --rays 1024 --kinds primary --no-embree --repeat 1 --save-rays " +
                       dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(std::filesystem::file_size(dir / "primary.rays"), 1024u * 32u);
  EXPECT_EQ(std::filesystem::file_size(dir / "ao.rays") % 32u, 0u);
  EXPECT_GT(std::filesystem::file_size(dir / "diffuse.rays"), 0u);
  EXPECT_EQ(std::filesystem::file_size(dir / "triangles.bin") % 36u, 0u);
  const Result t = run("trace --rays " + (dir / "primary.rays").string() + " --hits " +
                       (dir / "hits.bin").string());
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_EQ(std::filesystem::file_size(dir / "hits.bin"), 1024u * 16u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hrpp
