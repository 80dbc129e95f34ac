// host/app/: the hrpp command line as a user meets it: help, statistics, the triangle dump, the
// scene export, and one-line errors with a non-zero exit for bad files and flags.
#include <sys/wait.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "scene/load_scene.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
using test::read_file;

class Cli : public test::CliTest {
 protected:
  fs::path write(const std::string& name, const std::string& content) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

  // A bad input must end in exactly one line on stderr, naming `needle`, and exit status 1.
  void expect_one_line_error(const Result& r, const std::string& needle) const {
    EXPECT_EQ(r.status, 1) << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not one line: " << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("hrpp: error: ", 0), 0u) << r.err;
  }
};

TEST_F(Cli, HelpListsTheSubcommandAndItsOptions) {
  const Result top = run("--help");
  EXPECT_EQ(top.status, 0);
  EXPECT_NE(top.out.find("scene"), std::string::npos);
  const Result sub = run("scene --help");
  EXPECT_EQ(sub.status, 0);
  for (const char* opt : {"--json", "--dump-triangles", "--bvh-bins", "--bvh-max-leaf"})
    EXPECT_NE(sub.out.find(opt), std::string::npos) << opt;
}

// One shared option group (host/app/shared_options.h): the scene and --bvh-* everywhere, the
// device's options on the commands that open it.
TEST_F(Cli, EverySceneCommandListsTheSharedOptions) {
  for (const char* command : {"scene", "trace", "bench", "render"}) {
    const Result r = run(std::string(command) + " --help");
    ASSERT_EQ(r.status, 0) << command;
    // (CLI11 2.1 writes a default as "scene TEXT=builtin:cornell", 2.4 as "[builtin:cornell]".)
    for (const char* opt : {"scene TEXT", "builtin:cornell", "--bvh-bins", "--bvh-max-leaf"})
      EXPECT_NE(r.out.find(opt), std::string::npos) << command << " " << opt;
    if (std::string(command) == "scene") continue;
    for (const char* opt : {"--device", "--validate", "--vulkan-validate", "--rays-per-invocation"})
      EXPECT_NE(r.out.find(opt), std::string::npos) << command << " " << opt;
  }
}

TEST_F(Cli, SceneDefaultsToTheCornellBox) {
  const Result r = run("scene");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("builtin:cornell"), std::string::npos);
  EXPECT_NE(r.out.find("SAH cost"), std::string::npos);
}

TEST_F(Cli, SceneJsonHasSceneAndBvhStatistics) {
  const Result r = run("scene builtin:cornell --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const Scene scene = builtin_cornell();
  EXPECT_EQ(j.at("triangles").get<std::size_t>(), scene.triangles.size());
  EXPECT_GT(j.at("bvh").at("sah_cost").get<double>(), 1.0);
  EXPECT_GE(j.at("bvh").at("leaves").get<int>(), 2);
  EXPECT_EQ(j.at("bvh").at("leaves").get<int>(), j.at("bvh").at("interior_nodes").get<int>() + 1);
}

TEST_F(Cli, TriangleDumpIsNineFloatsPerTriangleInIdOrder) {
  const fs::path dump = dir_ / "tris.bin";
  const Result r = run("scene builtin:cornell --dump-triangles " + dump.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const Scene scene = builtin_cornell();
  const std::string bytes = read_file(dump);
  ASSERT_EQ(bytes.size(), scene.triangles.size() * 9 * sizeof(float));
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    float f[9];
    std::memcpy(f, bytes.data() + i * sizeof(f), sizeof(f));
    const Triangle& t = scene.triangles[i];
    EXPECT_EQ(glm::vec3(f[0], f[1], f[2]), t.v0);
    EXPECT_EQ(glm::vec3(f[3], f[4], f[5]), t.v1);
    EXPECT_EQ(glm::vec3(f[6], f[7], f[8]), t.v2);
  }
}

// The scene export for another renderer (study/cycles_reference.py): the loaded scene's
// triangles, normals, materials, lights and cameras, as load_scene has them.
TEST_F(Cli, SceneExportHoldsTheLoadedScene) {
  const fs::path out = dir_ / "cornell.json";
  const Result r = run("scene builtin:cornell --export-json " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(out));
  const Scene scene = builtin_cornell();
  EXPECT_EQ(j["format"], "hrpp scene export 1");
  ASSERT_EQ(j["positions"].size(), scene.triangles.size() * 9);
  ASSERT_EQ(j["normals"].size(), scene.triangles.size() * 9);
  ASSERT_EQ(j["material_of"].size(), scene.triangles.size());
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    EXPECT_EQ(j["positions"][9 * i + 3].get<float>(), scene.triangles[i].v1.x);
    EXPECT_EQ(j["material_of"][i].get<std::uint32_t>(), scene.shading[i].material);
  }
  ASSERT_EQ(j["materials"].size(), scene.materials.size());
  const nlohmann::json& light = j["materials"][3];
  EXPECT_EQ(light["name"], "light");
  EXPECT_EQ(light["emission"][0].get<float>(), 17.0f);
  ASSERT_EQ(j["lights"].size(), 1u);
  EXPECT_EQ(j["lights"][0]["type"], "area");
  ASSERT_EQ(j["cameras"].size(), 1u);
  EXPECT_EQ(j["cameras"][0]["position"][2].get<float>(), scene.cameras[0].position.z);
  expect_one_line_error(run("scene --export-json " + (dir_ / "no/such/dir/s.json").string()),
                        "s.json");
}

TEST_F(Cli, MissingSceneFileIsAOneLineError) {
  expect_one_line_error(run("scene " + (dir_ / "nope.glb").string()), "nope.glb");
}

TEST_F(Cli, TruncatedGlbIsAOneLineError) {
  const std::string glb = read_file(fs::path(HRPP_TEST_SCENES_DIR) / "meshes/utah_teapot.glb");
  ASSERT_GT(glb.size(), 200u);
  const fs::path p = write("cut.glb", glb.substr(0, glb.size() / 2));
  expect_one_line_error(run("scene " + p.string()), "cut.glb");
}

TEST_F(Cli, BadManifestJsonIsAOneLineError) {
  const fs::path p = write("bad.scene.json", "{ \"objects\": [ { \"gltf\": ");
  expect_one_line_error(run("scene " + p.string()), "bad.scene.json");
}

TEST_F(Cli, UnknownBuiltinIsAOneLineError) {
  expect_one_line_error(run("scene builtin:nothing"), "builtin:nothing");
}

TEST_F(Cli, BadBvhSettingsAreOneLineErrors) {
  expect_one_line_error(run("scene --bvh-bins 1"), "--bvh-bins");
  expect_one_line_error(run("scene --bvh-max-leaf 0"), "--bvh-max-leaf");
}

TEST_F(Cli, UnwritableDumpPathIsAOneLineError) {
  expect_one_line_error(run("scene --dump-triangles " + (dir_ / "no/such/dir/t.bin").string()),
                        "t.bin");
}

TEST_F(Cli, UnknownOptionsFailWithoutACrash) {
  const Result r = run("scene --no-such-flag");
  EXPECT_NE(r.status, 0);
  EXPECT_LT(r.status, 128) << "crashed";
  EXPECT_NE(r.err.find("--no-such-flag"), std::string::npos) << r.err;
  EXPECT_NE(run("frobnicate").status, 0);
}

// --hrpp on without a GPU: HRPP inline in the CPU traversal beside the CPU reference, and in
// front of Embree beside Embree (where the build has it), their answers checked (exact: every
// one is HRPP off's) and their time ratios and counters printed.
TEST_F(Cli, BenchRunsHrppInlineOnTheCpu) {
  const fs::path json = dir_ / "bench.json";
  const Result r = run("bench builtin:cornell --no-gpu --hrpp on --hrpp-mode exact "
                       "--rays 8192 --repeat 1 --kinds primary,ao --json " + json.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("cpu-hrpp"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cpu-hrpp/cpu-ref"), std::string::npos) << r.out;
  const bool embree = r.out.find("Embree not available") == std::string::npos;
  if (embree) {
    EXPECT_NE(r.out.find("emb-hrpp/embree"), std::string::npos) << r.out;
  }
  const nlohmann::json j = nlohmann::json::parse(read_file(json));
  for (const nlohmann::json& kind : j["kinds"]) {
    ASSERT_TRUE(kind.contains("cpu_hrpp")) << kind.dump();
    EXPECT_EQ(kind.contains("embree_hrpp"), embree) << kind.dump();
    EXPECT_EQ(kind["cpu_hrpp"]["probes"], 8192) << kind["kind"];
    EXPECT_GT(kind["cpu_hrpp"]["time_over_off"].get<double>(), 0.0) << kind["kind"];
    for (const nlohmann::json& t : kind["tracers"])
      EXPECT_EQ(t["validation"]["mismatches"], 0) << t["tracer"];
  }
}

// The commit --version names: git's short hash (with "-dirty"), or "unknown" outside a checkout.
std::string version_commit(const Result& r) {
  const std::string prefix = "hrpp commit ";
  if (r.out.rfind(prefix, 0) != 0 || r.out.empty() || r.out.back() != '\n') return "";
  return r.out.substr(prefix.size(), r.out.size() - prefix.size() - 1);
}

// The value of a string attribute in an EXR header (OpenEXR keeps the header uncompressed);
// "(absent)" without one.
std::string exr_string(const std::string& exr, const std::string& name) {
  const std::string key = name + std::string("\0string\0", 8);
  const std::size_t at = exr.find(key);
  if (at == std::string::npos || at + key.size() + 4 > exr.size()) return "(absent)";
  std::uint32_t length = 0;
  std::memcpy(&length, exr.data() + at + key.size(), sizeof length);
  return exr.substr(at + key.size() + 4, length);
}

TEST_F(Cli, VersionNamesTheCommit) {
  const Result r = run("--version");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string commit = version_commit(r);
  EXPECT_TRUE(std::regex_match(commit, std::regex("[0-9a-f]{7,40}(-dirty)?|unknown"))) << r.out;
}

// The stats and the image record the command line, the commit and the device; so does bench's
// JSON (its device: "machine"'s "vulkan_device", null with --no-gpu).
TEST_F(Cli, ReportsAndImagesRecordTheCommandLineCommitAndDevice) {
  const std::string commit = version_commit(run("--version"));
  ASSERT_FALSE(commit.empty());
  const fs::path exr = dir_ / "x.exr", stats = dir_ / "s.json", bench = dir_ / "b c.json";
  const std::string args = "render --backend cpu --size 8x6 --spp 1 --out " + exr.string() +
                           " --stats " + stats.string();
  const Result r = run(args);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(stats));
  EXPECT_EQ(j.at("commit"), commit);
  const std::string line = j.at("command_line").get<std::string>();
  EXPECT_EQ(line, std::string(HRPP_BINARY) + " " + args);
  EXPECT_EQ(j.at("device").at("name"), "CPU reference renderer");
  const std::string image = read_file(exr);
  EXPECT_EQ(exr_string(image, "hrpp:commit"), commit);
  EXPECT_EQ(exr_string(image, "hrpp:command_line"), line);
  EXPECT_EQ(exr_string(image, "hrpp:device"), "CPU reference renderer");
#ifdef HRPP_HAVE_OIIO  // PNG: text chunks, keyword then value
  const fs::path png = dir_ / "x.png";
  ASSERT_EQ(run("render --backend cpu --size 8x6 --spp 1 --out " + png.string()).status, 0);
  EXPECT_NE(read_file(png).find("tEXthrpp:commit" + std::string(1, '\0') + commit),
            std::string::npos);
#endif
  ASSERT_EQ(run("bench --no-gpu --rays 64 --repeat 1 --kinds primary --json '" + bench.string() +
                "'").status, 0);
  const nlohmann::json b = nlohmann::json::parse(read_file(bench));
  EXPECT_EQ(b.at("commit"), commit);
  EXPECT_NE(b.at("command_line").get<std::string>().find(" --json '" + bench.string() + "'"),
            std::string::npos) << b.at("command_line");  // quoted again: the path holds a space
}

// The GPU stage's deterministic order has no meaning for HRPP inline in the CPU renderer.
TEST_F(Cli, CpuBackendRefusesTheStagesOrders) {
  for (const auto& [settings, key] : {std::pair{R"({"batch": 64})", "batch"},
                                      std::pair{R"({"serial": true})", "serial"}}) {
    const fs::path file = dir_ / "settings.json";
    std::ofstream(file) << settings;
    const Result r = run(std::string("render --backend cpu --hrpp on --size 8x8 --out ") +
                         (dir_ / "x.exr").string() + " --hrpp-config " + file.string());
    expect_one_line_error(r, std::string("--hrpp-config: ") + key);
    EXPECT_FALSE(fs::exists(dir_ / "x.exr")) << settings;
  }
}

}  // namespace
}  // namespace hrpp
