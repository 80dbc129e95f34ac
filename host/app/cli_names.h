// A name table (common/name_table.h) as a CLI11 option validator: the option takes one of the
// table's names and stores its value; --help and the error for any other word list the names.
#pragma once

#include <cstddef>
#include <string>

#include <CLI/CLI.hpp>

#include "common/name_table.h"

namespace hrpp::app {

// The name becomes its value's number, which CLI11 then stores in the enum (or bool) option.
template <class E, std::size_t N>
CLI::Validator one_of(const NameTable<E, N>& table) {
  return CLI::Validator(
      [table](std::string& input) -> std::string {
        for (const Named<E>& n : table) {
          if (input != n.name) continue;
          input = std::to_string(static_cast<long long>(n.value));
          return {};
        }
        return "'" + input + "' is not one of " + names_in(table);
      },
      "{" + names_in(table) + "}");
}

}  // namespace hrpp::app
