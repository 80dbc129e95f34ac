// The message of the hrpp::Error that `f` throws, or "" when it throws none (tests that check an
// error's text).
#pragma once

#include <functional>
#include <string>

#include "common/error.h"

namespace hrpp::test {

inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace hrpp::test
