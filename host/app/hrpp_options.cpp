#include "app/hrpp_options.h"

#include <algorithm>
#include <string>

#include "app/cli_names.h"
#include "app/hrpp_config_file.h"
#include "common/error.h"
#include "hrpp_interface.h"

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

namespace {

// A per-class option's value: a comma-separated list of "V" (every class) and "class=V" (that
// class), applied in order, V parsed by `parse`: "light" sets every class, "hrpp,shadow=light"
// every class but shadow to hrpp. Throws hrpp::Error naming `flag`.
template <class T, class Parse>
void parse_per_class(const std::string& text, const std::string& flag, PerClass<T>& out,
                     Parse parse) {
  try {
    PerClass<T> next = out;
    std::size_t start = 0;
    while (start <= text.size()) {
      const std::size_t end = std::min(text.find(',', start), text.size());
      const std::string item = text.substr(start, end - start);
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos) {
        const T v = parse(item);
        next = {{v, v, v}};
      } else {
        next[parse_ray_class(item.substr(0, eq))] = parse(item.substr(eq + 1));
      }
      start = end + 1;
    }
    out = next;
  } catch (const Error& e) {
    const std::string what = e.what();
    throw Error(what.rfind(flag + ":", 0) == 0 ? what : flag + ": " + what);
  }
}

}  // namespace

std::string ray_class_list(const PerClass<bool>& classes) {
  std::string s;
  for (RayClass c : kRayClasses)
    if (classes[c]) s += (s.empty() ? "" : ",") + std::string(ray_class_name(c));
  return s;
}

PredictorConfig HrppOptions::config(DeviceTracerKind tracer) const {
  return config_file.empty() ? build(tracer) : config_with_file(*this, tracer);
}

HrppOptions HrppOptions::overridden_by(const HrppOptions& cli) const {
  HrppOptions o = *this;
  for (const std::string& f : cli.given) {
    if (f == "--hrpp") o.enabled = cli.enabled;
    if (f == "--hrpp-rays") o.classes = cli.classes;
    if (f == "--hrpp-mode") o.mode = cli.mode;
    if (f == "--table-preset") {  // the whole table
      o.preset = cli.preset;
      o.sets = cli.sets;
      o.ways = cli.ways;
      o.nodes = cli.nodes;
      o.sm_tables = cli.sm_tables;
      o.policy = cli.policy;
    }
  }
  o.config_file.clear();
  o.given.clear();
  return o;
}

PredictorConfig HrppOptions::build(DeviceTracerKind tracer) const {
  PredictorConfig c;
  c.enabled = enabled;
  c.mode = mode;
  c.fallback = fallback.value_or(tracer == DeviceTracerKind::kRayQuery ? Fallback::kRoot
                                                                        : Fallback::kSkip);
  if (enabled && tracer == DeviceTracerKind::kRayQuery && c.fallback == Fallback::kSkip)
    throw Error("fallback skip: skip lists are the BVH kernels'; in front of the "
                "driver's ray queries use fallback root");
  for (RayClass k : kRayClasses) c.hash[k] = {hash[k], hash_bits[k], hash_dir_bits[k]};
  c.gate = gate;
  c.go_up = go_up;
  c.go_up_size = go_up_size;
  for (RayClass k : kRayClasses) {
    TableConfig& t = c.table[k];
    t = table_preset(preset[k]);
    if (sets[k]) t.sets = sets[k];
    if (ways[k]) t.ways = ways[k];
    if (nodes[k]) t.nodes = nodes[k];
    if (sm_tables[k]) t.sm_tables = sm_tables[k];
    if (policy[k]) t.policy = *policy[k];
  }
  if (batch > HRPP_INSERT_BATCH_MAX)
    throw Error("batch: at most " + std::to_string(HRPP_INSERT_BATCH_MAX) + " rays");
  c.batch = batch;
  c.pilot = batch > 0 ? 0 : pilot;
  c.serial = serial;
  c.count_baseline = count_baseline;
  c.classes = classes;
  c.adaptive = adaptive;  // with batches it does not adapt (PredictorConfig::adapts)
  for (RayClass k : kRayClasses) {  // checks sizes and precision now, naming the flag
    if (!c.predicts(k)) c.hash[k].dir_bits = 0;  // a list's V sets every class
    if (!c.predicts(k) || query_kind(k) == QueryKind::kAny) c.gate[k] = 0.0f;
    if (c.gate[k] > 0.0f && c.mode == PredictorMode::kExact)
      throw Error("gate: exact mode already bounds every true positive's trace");
    (void)make_predictor_params(c, k, Aabb{});
    if (c.predicts(k) && query_kind(k) != QueryKind::kAny && is_light_space(c.hash[k].kind))
      throw Error(std::string("hash: ") + hash_kind_name(c.hash[k].kind) +
                  " keys shadow rays (it reads the ray's end at the light), not " +
                  ray_class_name(k) + " rays");
  }
  return c;
}

// A number as go_up_size and gate are written: "0.02" (6 digits; no round trip needed).
std::string format_number(float x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(x));
  return buf;
}

// The --help default of a per-class option: "camera=V,bounce=W,shadow=X", or "V" if all agree.
template <class T, class Text>
std::string per_class_default(const PerClass<T>& v, Text text) {
  PredictorConfig every;
  every.enabled = true;
  return per_class_text(every, v, text);
}

// What every per-class option's help adds.
const char* const kPerClass =
    " (V: every ray class; a list of V and class=V, in order, e.g. tuned,shadow=beam; "
    "classes: camera, bounce, shadow)";

// --table-preset, per ray class (the sizes and the policy: --hrpp-config).
void add_table_options(CLI::App* cmd, HrppOptions& o, const std::string& g) {
  const std::string per_class = kPerClass;
  cmd->add_option_function<std::string>(
         "--table-preset",
         [&o](const std::string& v) {
           parse_per_class(v, "--table-preset", o.preset, [](const std::string& n) {
             return parse_in(kTablePresetNames, n, "unknown preset");
           });
         },
         "Table size: tuned (16384x2x1 lru, 512 KiB), beam (4096x2x4 lru, 224 KiB), small "
         "(1024x8x8 lru, 352 KiB), unbounded (131072x16x16, none, 152 MiB: the paper's limit "
         "study), tiny (4x2x2 lru), micro21 (2 SM tables of 256x4x1 micro21, 32 KiB: "
         "MICRO'21's; with its key: configs/hrpp/micro21.json)" +
             per_class)
      ->default_str(per_class_default(
          o.preset, [](TablePreset p) { return std::string(name_in(kTablePresetNames, p)); }))
      ->group(g);
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
  cmd->add_option("--hrpp-mode", o.mode,
                  "Hit-all: speculative (accept the closest predicted hit; can be wrong) or exact "
                  "(its t bounds a full traversal: same answers as --hrpp off)")
      ->transform(one_of(kPredictorModeNames))
      ->default_str(predictor_mode_name(o.mode))
      ->group(g);
  add_table_options(cmd, o, g);
  cmd->add_option("--hrpp-config", o.config_file,
                  "HRPP's settings from FILE.json: keys, tables, adaptive, fallback, gate, "
                  "batches and more, in the form of the \"hrpp\" object of a --stats JSON (or "
                  "that JSON itself), or any part of it (docs/HRPP.md, \"Settings file\"; "
                  "configs/hrpp/); the flags above given too override it")
      ->group(g);
  for (CLI::Option* opt : cmd->get_options())  // which flags the command line gives
    if (opt->get_group() == g && opt->get_name() != "--hrpp-config")
      opt->each([&o, name = opt->get_name()](const std::string&) { o.given.push_back(name); });
}

nlohmann::json class_names(const PredictorConfig& c) {
  nlohmann::json names = nlohmann::json::array();
  for (RayClass k : kRayClasses)
    if (c.classes[k]) names.push_back(ray_class_name(k));
  return names;
}

// A per-class number: the number when every predicting class has the same, else the
// "class=N,..." text.
template <class Value>
nlohmann::json per_class_number(const PredictorConfig& c, Value value) {
  PerClass<std::uint64_t> v;
  for (RayClass k : kRayClasses) v[k] = value(k);
  const std::string text = per_class_text(c, v, [](std::uint64_t n) { return std::to_string(n); });
  if (text.find('=') != std::string::npos) return text;
  return std::stoull(text);
}

// Every class's key, go-up rule and table, predicting or not: {"camera": {"hash", "hash_bits",
// "go_up", "go_up_size", "table_sets", ...}, ...}.
nlohmann::json class_keys(const PredictorConfig& c) {
  nlohmann::json keys = nlohmann::json::object();
  for (RayClass k : kRayClasses)
    keys[ray_class_name(k)] = {{"hash", hash_kind_name(c.hash[k].kind)},
                               {"hash_bits", c.hash[k].bits},
                               {"hash_dir_bits", c.hash[k].dir_bits},
                               {"gate", c.gate[k]},
                               {"go_up", c.go_up[k]},
                               {"go_up_size", c.go_up_size[k]},
                               {"table_sets", c.table[k].sets},
                               {"table_ways", c.table[k].ways},
                               {"table_nodes", c.table[k].nodes},
                               {"table_policy", table_policy_name(c.table[k].policy)},
                               {"sm_tables", c.table[k].sm_tables},
                               {"table_bytes", c.table_bytes(k)}};
  return keys;
}

nlohmann::json predictor_config_json(const PredictorConfig& c) {
  return {{"enabled", c.enabled},
          {"hash",
           per_class_text(c, c.hash, [](const HashConfig& h) { return hash_kind_name(h.kind); })},
          {"hash_bits", per_class_number(c, [&c](RayClass k) { return c.hash[k].bits; })},
          {"mode", predictor_mode_name(c.mode)},
          {"gate", per_class_text(c, c.gate, format_number)},
          {"fallback", fallback_name(c.fallback)},
          {"go_up", per_class_number(c, [&c](RayClass k) { return c.go_up[k]; })},
          {"go_up_size", per_class_text(c, c.go_up_size, format_number)},
          {"keys", class_keys(c)},
          {"table_sets", per_class_number(c, [&c](RayClass k) { return c.table[k].sets; })},
          {"table_ways", per_class_number(c, [&c](RayClass k) { return c.table[k].ways; })},
          {"table_nodes", per_class_number(c, [&c](RayClass k) { return c.table[k].nodes; })},
          {"table_policy", per_class_text(c, c.table,
                                          [](const TableConfig& t) {
                                            return std::string(table_policy_name(t.policy));
                                          })},
          {"table_bytes", per_class_number(c, [&c](RayClass k) { return c.table_bytes(k); })},
          {"sm_tables", per_class_number(c, [&c](RayClass k) { return c.table[k].sm_tables; })},
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
