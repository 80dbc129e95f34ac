// One error type for everything the user can get wrong (files, flags, scenes). Its message is a
// single line that names the file or flag; the CLI prints it and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace hrpp {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace hrpp
