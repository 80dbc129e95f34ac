// Test helpers shared by the glTF loader's suites (scene_test, gltf_encodings_test): a fixture
// with a fresh temporary directory that writes GltfWriter files into it and loads them, and the
// check that a call fails with one line naming the file.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

#include "common/error.h"
#include "gltf_writer.h"
#include "scene/load_scene.h"

namespace hrpp::test {

// Runs f, expects an hrpp::Error with a one-line message that starts with `file` (the path as
// passed) and contains `fragment`; returns the message.
inline std::string expect_error(const std::function<void()>& f, const std::string& file,
                                const std::string& fragment = "") {
  try {
    f();
  } catch (const hrpp::Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_EQ(msg.rfind(file, 0), 0u) << "message does not start with " << file << ": " << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "missing '" << fragment << "': " << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an hrpp::Error: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

class GltfFileTest : public ::testing::Test {
 public:
  const std::filesystem::path& dir() const { return dir_; }

 protected:
  void SetUp() override { dir_ = make_temp_dir(tag()); }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  // Writes w to dir_/name and loads it.
  Scene load(const GltfWriter& w, const std::string& name = "s.glb") {
    w.write(dir_ / name);
    return load_gltf(dir_ / name);
  }
  std::string path(const std::string& name = "s.glb") const { return (dir_ / name).string(); }
  // The temporary directory's tag: the test suite's name.
  static std::string tag() {
    return ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name();
  }
  std::filesystem::path dir_;
};

}  // namespace hrpp::test
