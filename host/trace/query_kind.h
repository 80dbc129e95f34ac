// The two kinds of ray query: closest hit (hit-all: the nearest triangle, its t, u, v) and any
// hit (hit-any, occlusion: is there a triangle within [tmin, tmax]?). Every tracer answers both;
// a kernel, a queue or an array per kind is indexed by index_of(kind).
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/name_table.h"

namespace hrpp {

enum class QueryKind : std::uint8_t { kClosest, kAny };

inline constexpr NameTable<QueryKind, 2> kQueryKindNames = {
    {{QueryKind::kClosest, "closest"}, {QueryKind::kAny, "any"}}};
inline constexpr std::array<QueryKind, 2> kQueryKinds = {QueryKind::kClosest, QueryKind::kAny};

constexpr std::size_t index_of(QueryKind k) { return static_cast<std::size_t>(k); }
constexpr const char* query_kind_name(QueryKind k) { return name_in(kQueryKindNames, k); }
// "hit-all" / "hit-any": the paper's words, used in buffer names and reports.
constexpr const char* query_kind_label(QueryKind k) {
  return k == QueryKind::kAny ? "hit-any" : "hit-all";
}

}  // namespace hrpp
