// One name table per enum: its values and their names, written once, and everything made from
// it: the name function, the parser (one-line error listing the names), the CLI11 validator
// (app/cli_names.h) and the list for help texts. A new value is one line in its table.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "common/error.h"

namespace hrpp {

template <class E>
struct Named {
  E value;
  const char* name;
};

template <class E, std::size_t N>
using NameTable = std::array<Named<E>, N>;

// The value's name; "?" for a value not in the table.
template <class E, std::size_t N>
constexpr const char* name_in(const NameTable<E, N>& table, E value) {
  for (const Named<E>& n : table)
    if (n.value == value) return n.name;
  return "?";
}

// "a, b, c": the names in table order.
template <class E, std::size_t N>
std::string names_in(const NameTable<E, N>& table) {
  std::string s;
  for (const Named<E>& n : table) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

// The value named `name`; otherwise throws hrpp::Error("<what> 'name' (a, b, c)"), e.g. with
// what = "hash: unknown hash".
template <class E, std::size_t N>
E parse_in(const NameTable<E, N>& table, std::string_view name, std::string_view what) {
  for (const Named<E>& n : table)
    if (name == n.name) return n.value;
  throw Error(std::string(what) + " '" + std::string(name) + "' (" + names_in(table) + ")");
}

// name -> value.
template <class E, std::size_t N>
std::map<std::string, E> value_map(const NameTable<E, N>& table) {
  std::map<std::string, E> m;
  for (const Named<E>& n : table) m.emplace(n.name, n.value);
  return m;
}

}  // namespace hrpp
