// Where a run's outputs came from: the command line, the build's commit and the device. The
// --stats and --json reports record the first two as "command_line" and "commit" (the device
// they already name); the rendered image records all three in its metadata.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "render/image_output.h"

namespace hrpp::app {

// The commit this binary was built from: git's short hash, "-dirty" appended when tracked files
// differed from it, or "unknown" (built outside a git checkout). Defined by a source generated
// at every build (cmake/write_build_commit.cmake).
std::string_view build_commit();

// main() records its arguments once. command_line(): them joined by spaces, each one with a
// space or a character the shell would read quoted in single quotes, bytes that are not UTF-8
// as '?' (the reports are JSON).
void set_command_line(int argc, const char* const* argv);
const std::string& command_line();

// Adds "command_line" and "commit" to a report.
void add_provenance(nlohmann::json& report);

// The image's metadata: "Software" ("hrpp <commit>"), "hrpp:commit", "hrpp:command_line" and
// "hrpp:device" (`device`: the device's name).
ImageAttributes image_provenance(const std::string& device);

}  // namespace hrpp::app
