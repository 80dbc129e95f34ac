#include "app/output_path.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/interrupt.h"

namespace hrpp::app {

void check_output_path(const std::string& path, const std::string& flag) {
  if (path.empty()) return;
  namespace fs = std::filesystem;
  const fs::path p(path);
  std::error_code ec;
  auto fail = [&](const std::string& why) { throw Error(flag + " " + path + ": " + why); };
  if (fs::is_directory(p, ec)) fail("is a directory");
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::exists(dir, ec)) fail("directory " + dir.string() + " does not exist");
  if (!fs::is_directory(dir, ec)) fail(dir.string() + " is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    fail("directory " + dir.string() + " is not writable (" + std::strerror(errno) + ")");
  }
  if (fs::exists(p, ec) && ::access(p.c_str(), W_OK) != 0) {
    fail("is not writable (" + std::string(std::strerror(errno)) + ")");
  }
}

void write_file_atomically(const std::string& path, std::string_view bytes,
                           const std::string& what) {
  // The process id in the name: two processes writing one path never share a temporary.
  const std::string tmp = path + ".partial-" + std::to_string(::getpid());
  std::error_code ec;
  set_file_being_written(tmp.c_str());
  struct Clear {
    ~Clear() { set_file_being_written(nullptr); }
  } clear;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(path + ": " + what + ": " + std::strerror(errno));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      throw Error(path + ": " + what);
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(path + ": " + what + ": " + ec.message());
  }
}

}  // namespace hrpp::app
