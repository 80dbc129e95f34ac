#include "app/hrpp_options.h"

#include <algorithm>
#include <string>

#include "app/cli_names.h"
#include "common/error.h"

namespace hrpp::app {

PerClass<bool> parse_ray_classes(const std::string& list) {
  PerClass<bool> on{};
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t end = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, end - start);
    if (name == "all" || name == "both") on[RayClass::kCamera] = on[RayClass::kBounce] = true;
    if (name == "any" || name == "both") on[RayClass::kShadow] = true;
    if (name != "all" && name != "any" && name != "both") {
      try {
        on[parse_ray_class(name)] = true;
      } catch (const Error& e) {
        throw Error(std::string("--hrpp-rays: ") + e.what());
      }
    }
    start = end + 1;
  }
  return on;
}

std::string ray_class_list(const PerClass<bool>& classes) {
  std::string s;
  for (RayClass c : kRayClasses)
    if (classes[c]) s += (s.empty() ? "" : ",") + std::string(ray_class_name(c));
  return s;
}

PredictorConfig HrppOptions::config() const {
  PredictorConfig c;
  c.enabled = enabled;
  c.mode = mode;
  c.hash = {hash, hash_bits};
  c.go_up = go_up;
  c.table = table_preset(preset);
  if (sets) c.table.sets = sets;
  if (ways) c.table.ways = ways;
  if (nodes) c.table.nodes = nodes;
  if (policy) c.table.policy = *policy;
  c.batch = batch;
  c.pilot = batch > 0 ? 0 : pilot;
  c.serial = serial;
  c.count_baseline = count_baseline;
  c.classes = classes;
  c.adaptive = adaptive;  // with batches it does not adapt (PredictorConfig::adapts)
  (void)make_predictor_params(c, Aabb{});  // checks sizes and precision now, naming the flag
  return c;
}

void add_hrpp_options(CLI::App* cmd, HrppOptions& o) {
  const std::string g = "HRPP (hash-based ray path prediction)";
  static constexpr NameTable<bool, 2> kOnOff = {{{false, "off"}, {true, "on"}}};
  cmd->add_option("--hrpp", o.enabled, "Probe a predictor table before traversal: off | on")
      ->transform(one_of(kOnOff))
      ->default_str("off")
      ->group(g);
  cmd->add_option_function<std::string>(
         "--hrpp-rays", [&o](const std::string& list) { o.classes = parse_ray_classes(list); },
         "Ray classes that predict: a comma-separated subset of " + names_in(kRayClassNames))
      ->default_str(ray_class_list(o.classes))
      ->group(g);
  cmd->add_option("--hrpp-adaptive", o.adaptive,
                  "render: per frame and ray class, sample first and predict every ray only "
                  "where a sample saves time, sampling again now and then: on | off (every named "
                  "class predicts every ray, every frame; also with --hrpp-batch)")
      ->transform(one_of(kOnOff))
      ->default_str("on")
      ->group(g);
  cmd->add_option("--hrpp-mode", o.mode,
                  "Hit-all: speculative (accept the closest predicted hit; can be wrong) or exact "
                  "(its t bounds a full traversal: same answers as --hrpp off)")
      ->transform(one_of(kPredictorModeNames))
      ->default_str(predictor_mode_name(o.mode))
      ->group(g);
  cmd->add_option("--hash", o.hash,
                  "Ray hash: hrpp (the paper's IEEE-754 bits), grid-spherical, "
                  "two-point")
      ->transform(one_of(kHashKindNames))
      ->default_str(hash_kind_name(o.hash))
      ->group(g);
  cmd->add_option("--hash-bits", o.hash_bits, "Hash precision N (1..8)")
      ->capture_default_str()
      ->group(g);
  cmd->add_option("--go-up", o.go_up,
                  "Go-up level: predict the ancestor L levels above the leaf that held the hit")
      ->capture_default_str()
      ->group(g);
  cmd->add_option("--table-preset", o.preset,
                  "Table size per ray class: tuned (16384x2x1 lru, 512 KiB), small (1024x8x8 "
                  "lru, 352 KiB), unbounded (131072x16x16, none, 152 MiB: the paper's limit "
                  "study), tiny (4x2x2 lru)")
      ->transform(one_of(kTablePresetNames))
      ->default_str(name_in(kTablePresetNames, o.preset))
      ->group(g);
  cmd->add_option("--table-sets", o.sets, "Sets (a power of two; overrides the preset)")->group(g);
  cmd->add_option("--table-ways", o.ways, "Ways per set (overrides the preset)")->group(g);
  cmd->add_option("--table-nodes", o.nodes, "Nodes per entry (overrides the preset)")->group(g);
  cmd->add_option_function<TablePolicy>(
         "--table-policy", [&o](const TablePolicy& p) { o.policy = p; },
         "When full: none (drop), lru (evict the least recently used) or fifo (evict the "
         "oldest key; probe hits write nothing) (overrides the preset)")
      ->transform(one_of(kTablePolicyNames))
      ->group(g);
  cmd->add_option("--hrpp-batch", o.batch,
                  "Deterministic order: rays in batches of K probe the table the previous "
                  "batches left; inserts applied after each batch in ray order (0: inserts "
                  "during the trace)")
      ->capture_default_str()
      ->group(g);
  cmd->add_option("--hrpp-pilot", o.pilot,
                  "Pilot schedule: each trace predicts and traces every K-th ray first, so the "
                  "others find their entries (0: one round; ignored with --hrpp-batch)")
      ->capture_default_str()
      ->group(g);
  cmd->add_flag("--hrpp-serial", o.serial,
                "One ray per subgroup: the CPU reference's node order (with --hrpp-batch, "
                "counters a CPU reference predictor reproduces exactly)")
      ->group(g);
  cmd->add_flag("--hrpp-count", o.count_baseline,
                "render: also count what full traversals would visit (savings %); adds a "
                "counting traversal to the timed work (trace and bench count in a separate run)")
      ->group(g);
}

nlohmann::json class_names(const PredictorConfig& c) {
  nlohmann::json names = nlohmann::json::array();
  for (RayClass k : kRayClasses)
    if (c.classes[k]) names.push_back(ray_class_name(k));
  return names;
}

nlohmann::json predictor_config_json(const PredictorConfig& c) {
  return {{"enabled", c.enabled},
          {"hash", hash_kind_name(c.hash.kind)},
          {"hash_bits", c.hash.bits},
          {"mode", predictor_mode_name(c.mode)},
          {"go_up", c.go_up},
          {"table_sets", c.table.sets},
          {"table_ways", c.table.ways},
          {"table_nodes", c.table.nodes},
          {"table_policy", table_policy_name(c.table.policy)},
          {"table_bytes", c.table.bytes()},
          {"ray_classes", class_names(c)},
          {"adaptive", c.adapts()},
          {"count_baseline", c.count_baseline},
          {"batch", c.batch},
          {"pilot", c.pilot},
          {"serial", c.serial}};
}

nlohmann::json predictor_summary_json(const PredictorSummary& s) {
  nlohmann::json j = {{"interior_visited", s.trace.interior_visited},
                      {"leaves_visited", s.trace.leaves_visited},
                      {"triangles_tested", s.trace.triangles_tested},
                      {"table_entries", s.occupancy.entries},
                      {"table_nodes", s.occupancy.nodes},
                      {"table_capacity", s.occupancy.capacity},
                      {"table_bytes", s.occupancy.bytes},
                      {"hit_rate", s.hit_rate},
                      {"true_positive_rate", s.tp_rate},
                      {"false_positive_rate", s.fp_rate}};
  for (const CounterKey& k : kPredictorCounterKeys)
    if (s.baseline || !is_baseline_counter(k.index)) j[k.key] = s.counters.c[k.index];
  if (s.baseline) {
    j["skipped_interior"] = s.skipped_interior;
    j["savings"] = s.savings;
    j["net_savings"] = s.net_savings;
  }
  return j;
}

}  // namespace hrpp::app
