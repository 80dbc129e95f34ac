#include "hrpp/predictor_stats.h"

#include <algorithm>
#include <cstdio>

#include "common/bytes.h"

namespace hrpp {
namespace {

double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

}  // namespace

PredictorSummary summarize(const gpu::PredictorCounters& counters, const TraversalCounters& trace,
                           const TableOccupancy& occupancy, bool baseline) {
  PredictorSummary s;
  s.counters = counters;
  s.trace = trace;
  s.occupancy = occupancy;
  s.baseline = baseline;
  const auto& c = counters.c;
  const auto d = [](std::uint64_t v) { return static_cast<double>(v); };
  s.hit_rate = ratio(d(c[HRPP_PC_PREDICTOR_HITS]), d(c[HRPP_PC_PROBES]));
  s.tp_rate = ratio(d(c[HRPP_PC_TRUE_POSITIVES]), d(c[HRPP_PC_PREDICTOR_HITS]));
  s.fp_rate = ratio(d(c[HRPP_PC_FALSE_POSITIVES]), d(c[HRPP_PC_PREDICTOR_HITS]));
  if (baseline) {
    const auto base = static_cast<std::int64_t>(c[HRPP_PC_BASELINE_INTERIOR]);
    const auto verify = static_cast<std::int64_t>(c[HRPP_PC_VERIFY_INTERIOR]);
    const auto from_root = static_cast<std::int64_t>(trace.interior_visited) - verify;
    s.skipped_interior = base - from_root;
    s.savings = ratio(static_cast<double>(s.skipped_interior), static_cast<double>(base));
    s.net_savings =
        ratio(static_cast<double>(s.skipped_interior - verify), static_cast<double>(base));
  }
  return s;
}

namespace {

// A setting's number as the flags take it ("0.02", "1.4").
std::string number_text(float x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", static_cast<double>(x));
  return text;
}

}  // namespace

std::string describe(const PredictorConfig& config) {
  PerClass<std::string> tables;
  for (RayClass c : kRayClasses) {
    const TableConfig& t = config.table[c];
    const std::string per_sm =
        t.sm_tables > 1 ? " in each of " + std::to_string(t.sm_tables) + " SM tables" : "";
    tables[c] = std::to_string(t.sets) + "x" + std::to_string(t.ways) + "x" +
                std::to_string(t.nodes) + " " + table_policy_name(t.policy) + per_sm + " (" +
                format_bytes(config.table_bytes(c)) + ")";
  }
  const std::string table = per_class_text(config, tables, [](const std::string& s) { return s; });
  char buf[640];
  const std::string hash = per_class_text(config, config.hash, [](const HashConfig& h) {
    return std::string(hash_kind_name(h.kind)) + " N=" + std::to_string(h.bits) +
           (h.dir_bits > 0 ? " D=" + std::to_string(h.dir_bits) : "");
  });
  PerClass<std::string> levels;
  for (RayClass c : kRayClasses)
    levels[c] = std::to_string(config.go_up[c]) +
                (config.go_up_size[c] > 0.0f ? " size " + number_text(config.go_up_size[c]) : "");
  const std::string go_up = per_class_text(config, levels, [](const std::string& s) { return s; });
  std::string mode = predictor_mode_name(config.mode);
  if (std::ranges::any_of(kRayClasses, [&](RayClass c) { return config.gate[c] > 0.0f; }))
    mode += " with distance gate " + per_class_text(config, config.gate, number_text);
  std::snprintf(buf, sizeof buf, "hash %s, go-up %s, %s, table %s per ray class, %s", hash.c_str(),
                go_up.c_str(), mode.c_str(), table.c_str(),
                config.batch == 0 ? "inserts during the trace"
                                  : ("batches of " + std::to_string(config.batch) +
                                     (config.serial ? ", one ray per subgroup" : ""))
                                        .c_str());
  return buf;
}

std::string format_summary(const std::string& label, const PredictorSummary& s, QueryKind kind) {
  const auto& c = s.counters.c;
  const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
  char buf[1400];
  int n = std::snprintf(
      buf, sizeof buf,
      "%-11s probes %llu, predictor hits %llu (%.1f%%): true positives %llu (%.1f%%), false "
      "positives %llu; negatives %llu\n"
      "%-11s inserts %llu of %llu requests (present %llu, dropped %llu), evictions %llu; table "
      "%llu of %llu entries, %llu nodes, %s\n"
      "%-11s verification: %llu interior nodes, %llu leaves, %llu triangles\n",
      label.c_str(), u(c[HRPP_PC_PROBES]), u(c[HRPP_PC_PREDICTOR_HITS]), 100.0 * s.hit_rate,
      u(c[HRPP_PC_TRUE_POSITIVES]), 100.0 * s.tp_rate, u(c[HRPP_PC_FALSE_POSITIVES]),
      u(c[HRPP_PC_NEGATIVES]), "", u(c[HRPP_PC_INSERTS]), u(c[HRPP_PC_INSERT_REQUESTS]),
      u(c[HRPP_PC_INSERT_PRESENT]), u(c[HRPP_PC_INSERT_DROPS]), u(c[HRPP_PC_EVICTIONS]),
      u(s.occupancy.entries), u(s.occupancy.capacity), u(s.occupancy.nodes),
      format_bytes(s.occupancy.bytes).c_str(), "", u(c[HRPP_PC_VERIFY_INTERIOR]),
      u(c[HRPP_PC_VERIFY_LEAVES]), u(c[HRPP_PC_VERIFY_TRIANGLES]));
  if (s.baseline && n > 0 && static_cast<std::size_t>(n) < sizeof buf) {
    n += std::snprintf(
        buf + n, sizeof buf - static_cast<std::size_t>(n),
        "%-11s interior nodes %llu with HRPP, %llu without: skipped %lld, savings "
        "%.1f%%, net of verification %.1f%%%s\n",
        "", u(s.trace.interior_visited - c[HRPP_PC_VERIFY_INTERIOR]),
        u(c[HRPP_PC_BASELINE_INTERIOR]), static_cast<long long>(s.skipped_interior),
        100.0 * s.savings, 100.0 * s.net_savings,
        kind == QueryKind::kAny
            ? ""
            : (", wrong closest hits " + std::to_string(c[HRPP_PC_WRONG_CLOSEST]) +
               (c[HRPP_PC_GATED] > 0 ? ", gated " + std::to_string(c[HRPP_PC_GATED]) : ""))
                  .c_str());
  }
  return buf;
}

}  // namespace hrpp
