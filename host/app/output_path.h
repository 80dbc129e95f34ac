// Output files named on the command line. Every command checks its output paths before it
// loads a scene or touches the GPU, so a bad path costs nothing and never leaves one output
// written while another failed; files are written next to the target and renamed into place.
#pragma once

#include <string>
#include <string_view>

namespace hrpp::app {

// Throws hrpp::Error "FLAG PATH: <why>" unless PATH can be created or replaced: its directory
// exists and is writable, and PATH itself is not a directory. An empty PATH passes (not asked).
void check_output_path(const std::string& path, const std::string& flag);

// Writes bytes to PATH.partial and renames it to PATH; on any error removes the partial file
// and throws hrpp::Error naming PATH and `what` (e.g. "cannot write stats").
void write_file_atomically(const std::string& path, std::string_view bytes,
                           const std::string& what);

}  // namespace hrpp::app
