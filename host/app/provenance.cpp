#include "app/provenance.h"

namespace hrpp::app {
namespace {

std::string& recorded_command_line() {
  static std::string line;
  return line;
}

// `arg` as the shell would read it back: as is when it holds only safe characters, else in
// single quotes (a quote inside as '\'').
std::string shell_quoted(const std::string& arg) {
  static constexpr std::string_view kSafe =
      "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789@%+=:,./_-";
  if (!arg.empty() && arg.find_first_not_of(kSafe) == std::string::npos) return arg;
  std::string out = "'";
  for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Bytes that are not UTF-8 become '?': nlohmann::json refuses to write them.
std::string valid_utf8(std::string s) {
  try {
    (void)nlohmann::json(s).dump();
  } catch (const nlohmann::json::type_error&) {
    for (char& c : s)
      if (static_cast<unsigned char>(c) >= 0x80) c = '?';
  }
  return s;
}

}  // namespace

void set_command_line(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) line += (i ? " " : "") + shell_quoted(argv[i]);
  recorded_command_line() = valid_utf8(line);
}

const std::string& command_line() { return recorded_command_line(); }

void add_provenance(nlohmann::json& report) {
  report["command_line"] = command_line();
  report["commit"] = std::string(build_commit());
}

ImageAttributes image_provenance(const std::string& device) {
  const std::string commit(build_commit());
  return {{"Software", "hrpp " + commit},
          {"hrpp:commit", commit},
          {"hrpp:command_line", command_line()},
          {"hrpp:device", valid_utf8(device)}};
}

}  // namespace hrpp::app
