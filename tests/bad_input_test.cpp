// Bad input end to end: every malformed scene and manifest of tests/data/bad/ (made by
// tests/data/bad/make_bad.py) and bad command-line values end in one line on stderr that names
// the file or flag and the problem, exit status 1, no crash, and no output file left behind.
// The loader is checked in-process too (so the ASan build sees it) and through the hrpp binary.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_runner.h"
#include "common/error.h"
#include "scene/load_scene.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

const fs::path kBad = fs::path(HRPP_TEST_DATA_DIR) / "bad";

// Corpus file (relative to tests/data/bad/) → what its error message must say.
const std::map<std::string, std::string>& expected_errors() {
  static const std::map<std::string, std::string> m = {
      // containers
      {"gltf/truncated.glb", "truncated: the header says 388 bytes, the file has 194"},
      {"gltf/truncated_header.glb", "Too short"},
      {"gltf/wrong_magic.glb", "Invalid magic"},
      {"gltf/version1.glb", "GLB version 1 is not supported"},
      {"gltf/chunk_length.glb", "Invalid glTF binary"},
      {"gltf/bin_chunk_past_end.glb", "the BIN chunk (44 bytes) lies past the end of the file"},
      // found by fuzz_gltf: a truncated Draco file, which the meshopt/Draco pre-pass must not
      // rebuild into a consistent-looking one
      {"gltf/fuzz_truncated_draco.glb", "truncated: the header says 4976 bytes, the file has 4974"},
      {"gltf/corrupted_json_chunk.glb", "parse error"},
      {"gltf/empty.gltf", "JSON string too short"},
      {"gltf/binary_garbage.gltf", "parse error"},
      {"gltf/json_syntax.gltf", "missing closing quote"},
      {"gltf/json_array.gltf", "Root element is not a JSON object"},
      {"gltf/deep_extras.gltf", "JSON nested 513 levels deep (at most 512)"},
      // references and ranges
      {"gltf/accessor_past_view.gltf", "accessor 0 reads past the end of buffer 0"},
      {"gltf/view_past_buffer.gltf", "bufferView 0 lies past the end of buffer 0"},
      {"gltf/accessor_missing.gltf", "POSITION: accessor 7 does not exist"},
      {"gltf/buffer_view_missing.gltf", "bufferView 3 does not exist"},
      {"gltf/index_out_of_range.gltf", "index 3 at element 2 is out of range (vertex count 3)"},
      {"gltf/huge_count.gltf", "accessor 0 reads past the end of buffer 0"},
      {"gltf/huge_offset.gltf", "accessor 0 reads past the end of buffer 0"},
      {"gltf/stride_too_small.gltf", "byteStride 4 is smaller than the element size 12"},
      {"gltf/position_vec2.gltf", "is FLOAT VEC2, expected FLOAT VEC3"},
      {"gltf/component_type_double.gltf", "invalid componentType 5130"},
      {"gltf/sparse_count_too_large.gltf", "accessor 0 (POSITION): sparse count 4 is not in 1..3"},
      {"gltf/no_position.gltf", "has no POSITION attribute"},
      {"gltf/mesh_missing.gltf", "mesh 5 does not exist"},
      {"gltf/material_missing.gltf", "material 2 does not exist"},
      // external files
      {"gltf/missing_buffer.gltf", "missing.bin"},
      {"gltf/buffer_is_directory.gltf", "is not a regular file"},
      {"gltf/buffer_length_mismatch.gltf", "Failed to decode 'uri'"},
      {"gltf/missing_texture.gltf", "image 0: file missing.png not found or unreadable"},
      {"gltf/corrupt_texture.gltf", "image 0: Unknown image format"},
      {"gltf/huge_texture.gltf", "image 0: PNG of 100000 x 100000 pixels, larger than 16384"},
      {"gltf/huge_jpeg_texture.gltf", "image 0: JPEG of 60000 x 40000 pixels, larger than 16384"},
      // primitives and values
      {"gltf/mode_points.gltf", "no triangles: only 1 points/lines primitive (not surfaces)"},
      {"gltf/mode_lines.gltf", "no triangles: only 1 points/lines primitive (not surfaces)"},
      {"gltf/mode_invalid.gltf", "mode 9 (unknown) is not supported"},
      {"gltf/nan_vertex.gltf", "non-finite value (NaN or Inf) at element 1"},
      {"gltf/inf_vertex.gltf", "non-finite value (NaN or Inf) at element 2"},
      {"gltf/overflowing_transform.gltf", "out of float range after the node transform"},
      {"gltf/matrix_wrong_length.gltf", "matrix has 3 numbers, expected 16"},
      {"gltf/required_extension.gltf",
       "extension KHR_texture_basisu is required by the file but not supported"},
      // scenes and node graphs
      {"gltf/no_scene.gltf", "glTF has no scene"},
      {"gltf/empty_scene.gltf", "scene has no triangles"},
      {"gltf/only_degenerate_triangles.gltf", "all 1 are degenerate"},
      {"gltf/default_scene_missing.gltf", "default scene 3 does not exist"},
      {"gltf/cyclic_nodes.gltf", "node graph has a cycle through node 0"},
      {"gltf/self_parent_node.gltf", "node graph has a cycle through node 0"},
      {"gltf/child_missing.gltf", "node 9 does not exist"},
      {"gltf/exponential_instances.gltf", "the node graph reuses nodes more than 65536 times"},
      // found by fuzz_gltf: a 10 s timeout under ASan with the limit at 2^20, then at 2^18
      {"gltf/fuzz_dag_timeout.gltf", "the node graph reuses nodes more than 65536 times"},
      // manifests
      {"manifest/json_syntax.scene.json", "JSON syntax error at byte 33"},
      {"manifest/not_an_object.scene.json", "the top level must be a JSON object"},
      {"manifest/empty.scene.json", "JSON syntax error at byte 1"},
      {"manifest/no_objects_key.scene.json", "objects: missing"},
      {"manifest/empty_objects.scene.json", "scene has no triangles"},
      {"manifest/missing_mesh.scene.json", "does_not_exist.glb not found"},
      {"manifest/mesh_is_directory.scene.json", "is a directory"},
      {"manifest/bad_mesh.scene.json", "truncated.glb: Invalid glTF binary"},
      {"manifest/unknown_key.scene.json", "colour: unknown key"},
      {"manifest/wrong_type.scene.json", "objects[0].quad.corner: expected an array of 3 numbers"},
      {"manifest/number_out_of_range.scene.json", "number overflow parsing '1e999'"},
      {"manifest/self_reference.scene.json", "\"asset\" object not found"},
  };
  return m;
}

std::vector<std::string> corpus_files() {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(kBad)) {
    if (!e.is_regular_file() || e.path().extension() == ".py") continue;
    files.push_back(fs::relative(e.path(), kBad).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(BadInputCorpus, EveryFileHasAnExpectedError) {
  const std::vector<std::string> files = corpus_files();
  ASSERT_FALSE(files.empty()) << kBad;
  for (const std::string& f : files) EXPECT_TRUE(expected_errors().count(f)) << f << " not listed";
  for (const auto& [f, msg] : expected_errors()) EXPECT_TRUE(fs::exists(kBad / f)) << f;
}

// In-process: load_scene() throws hrpp::Error, one line, naming the file and the problem.
TEST(BadInputCorpus, LoaderRefusesEachFileWithOneLine) {
  for (const auto& [f, msg] : expected_errors()) {
    const std::string path = (kBad / f).string();
    try {
      (void)load_scene(path);
      ADD_FAILURE() << f << " loaded";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << f << ": " << what;
      EXPECT_EQ(what.rfind(path, 0), 0u) << f << ": does not start with the file: " << what;
      EXPECT_NE(what.find(msg), std::string::npos) << f << ": " << what;
    }
  }
}

class BadInputCli : public test::CliTest {
 protected:
  // Exit status 1 (not a crash, not CLI11's own codes), one line "hrpp: error: ..." naming
  // `needle`, nothing on stdout.
  void expect_error(const std::string& args, const std::string& needle) const {
    expect_error(args, {needle});
  }
  // The same, the error naming every one of `needles`.
  void expect_error(const std::string& args, std::initializer_list<std::string> needles) const {
    const test::CliResult r = run(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("hrpp: error: ", 0), 0u) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    for (const std::string& needle : needles)
      EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << args << ": " << r.out;
  }
  // No file at `path` and no temporary of any process beside it (NAME.partial-PID...).
  static void expect_absent(const fs::path& path) {
    EXPECT_FALSE(fs::exists(path)) << path;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(path.parent_path(), ec)) {
      EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
    }
  }
  fs::path write_bytes(const std::string& name, std::size_t bytes) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << std::string(bytes, '\0');
    return p;
  }
};

// One file per kind of problem through the binary (each run costs ~0.4 s of start-up; the
// in-process test above covers every file).
TEST_F(BadInputCli, CorpusFilesThroughTheBinary) {
  for (const std::string f :
       {"gltf/truncated.glb", "gltf/wrong_magic.glb", "gltf/json_syntax.gltf",
        "gltf/deep_extras.gltf", "gltf/huge_count.gltf", "gltf/index_out_of_range.gltf",
        "gltf/buffer_is_directory.gltf", "gltf/missing_texture.gltf", "gltf/mode_points.gltf",
        "gltf/nan_vertex.gltf", "gltf/required_extension.gltf", "gltf/cyclic_nodes.gltf",
        "gltf/exponential_instances.gltf", "manifest/missing_mesh.scene.json",
        "manifest/number_out_of_range.scene.json"}) {
    const std::string& msg = expected_errors().at(f);
    const fs::path dump = dir_ / "t.bin";
    expect_error("scene " + (kBad / f).string() + " --dump-triangles " + dump.string(), msg);
    expect_absent(dump);
  }
}

// Flags checked before any scene is loaded or device opened (so these need no Vulkan device).
TEST_F(BadInputCli, BadValuesNameTheFlag) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"render --size -5x5", "--size"},
      {"render --size 0x0", "--size"},
      {"render --size 100000x100000", "--size"},
      {"render --size 64", "--size"},
      {"render --spp -1", "--spp"},
      {"render --spp 0", "--spp"},
      {"render --spp 99999999999", "--spp"},
      {"render --spp 10000000", "--spp"},
      {"render --max-depth -1", "--max-depth"},
      {"render --max-depth 0", "--max-depth"},
      {"render --seed -3", "--seed"},
      {"render --frobnicate", "--frobnicate"},
      {"render --out image.txt", "image.txt"},
      {"trace --hits h.bin", "--rays"},
      {"trace --rays r.bin --hits h.bin --repeat 0", "--repeat"},
      {"trace --rays r.bin --hits h.bin --rays-per-invocation 0", "--rays-per-invocation"},
      {"bench --frobnicate", "--frobnicate"},
      {"scene --bvh-bins 1000", "--bvh-bins"},
      {"scene --bvh-max-leaf -1", "--bvh-max-leaf"},
      {"render --bvh-bins 1000", "--bvh-bins"},
      {"render --bvh-max-leaf 0", "--bvh-max-leaf"},
      {"scene --bvh-intersection-cost 0", "--bvh-intersection-cost"},
      {"scene --bvh-intersection-cost nan", "--bvh-intersection-cost"},
      {"render --backend cpu --bvh-nodes wide4", "--bvh-nodes wide4"},
      {"trace --rays r.bin --hits h.bin --bvh-nodes wide8", "--bvh-nodes"},
      {"render --rays-per-invocation 0", "--rays-per-invocation"},
      {"bench --rays-per-invocation 0", "--rays-per-invocation"},
      {"trace --rays r.bin --hits h.bin --memory foo", "--memory"},
      {"bench --memory device", "--memory"},
      {"render --memory 1", "--memory"},
      {"frobnicate", "frobnicate"},
  };
  for (const auto& [args, needle] : cases) expect_error(args, needle);
}

TEST_F(BadInputCli, RayFilesMustBeWhole32ByteRecords) {
  for (std::size_t bytes : {1u, 31u, 33u, 100u}) {
    const fs::path rays = write_bytes("r" + std::to_string(bytes) + ".bin", bytes);
    const fs::path hits = dir_ / "h.bin";
    expect_error("trace --rays " + rays.string() + " --hits " + hits.string(),
                 std::to_string(bytes) + " bytes is not a whole number of 32-byte ray records");
    expect_absent(hits);
  }
  expect_error("trace --rays " + (dir_ / "none.bin").string() + " --hits h.bin", "none.bin");
  expect_error("trace --rays " + dir_.string() + " --hits h.bin", dir_.string());
}

// A render or trace that cannot fit the device is refused before any upload with one line
// naming the scene, the bytes and the limit, and leaves no output. The heap check runs against
// the device's heap capped by HRPP_DEVICE_HEAP_MIB (the real heap is the host's memory on
// lavapipe); the image's own limit is the device's real maxStorageBufferRange.
TEST_F(BadInputCli, ScenesOverTheDeviceMemoryAreRefusedBeforeUpload) {
  const fs::path image = dir_ / "i.png", stats = dir_ / "s.json", hits = dir_ / "h.bin";
  const std::string outputs = " --out " + image.string() + " --stats " + stats.string();
  ::setenv("HRPP_DEVICE_HEAP_MIB", "1", 1);
  expect_error("render builtin:cornell --size 512x512 --spp 1" + outputs,
               {"more than the device's memory heap as capped by HRPP_DEVICE_HEAP_MIB of 1.00 MiB "
                "(1048576 bytes)",
                "largest: hit-all ray array 8.00 MiB"});
  expect_absent(image);
  expect_absent(stats);
  const fs::path rays = write_bytes("r.bin", 32 * 100000);
  expect_error("trace builtin:cornell --rays " + rays.string() + " --hits " + hits.string(),
               "hit-all ray array (3.05 MiB) does not fit beside the");
  expect_absent(hits);
  ::setenv("HRPP_DEVICE_HEAP_MIB", "lots", 1);
  expect_error("render builtin:cornell --size 8x8 --spp 1" + outputs,
               "HRPP_DEVICE_HEAP_MIB=lots: not a positive whole number of MiB");
  ::unsetenv("HRPP_DEVICE_HEAP_MIB");
  expect_error("render builtin:cornell --size 16384x16384 --spp 1" + outputs,
               "image is 4.00 GiB (4294967296 bytes), over the device's maxStorageBufferRange");
  expect_absent(image);
  expect_absent(stats);
}

// Output paths are checked before any work: nothing is written when one of them is bad.
TEST_F(BadInputCli, UnwritableOutputsFailFirstAndLeaveNothing) {
  const fs::path rays = write_bytes("r.bin", 64);
  const fs::path hits = dir_ / "h.bin", stats = dir_ / "s.json", image = dir_ / "i.png";
  const std::string missing_dir = (dir_ / "no" / "such").string();
  expect_error("trace --rays " + rays.string() + " --hits " + missing_dir + "/h.bin", "--hits");
  expect_error("trace --rays " + rays.string() + " --hits " + dir_.string(), "is a directory");
  expect_error("trace --rays " + rays.string() + " --hits " + hits.string() + " --stats " +
                   missing_dir + "/s.json",
               "--stats");
  expect_absent(hits);
  expect_error(
      "render --size 8x8 --spp 1 --out " + image.string() + " --stats " + missing_dir + "/s.json",
      "--stats");
  expect_absent(image);
  expect_error(
      "render --size 8x8 --spp 1 --out " + missing_dir + "/i.png --stats " + stats.string(),
      "--out");
  expect_absent(stats);
  expect_error("bench --json " + missing_dir + "/b.json", "--json");
  expect_error("scene --dump-triangles " + dir_.string(), "--dump-triangles");
  if (::geteuid() != 0) {  // root writes anywhere
    const fs::path ro = dir_ / "ro";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    expect_error("scene --dump-triangles " + (ro / "t.bin").string(), "not writable");
  }
}

}  // namespace
}  // namespace hrpp
