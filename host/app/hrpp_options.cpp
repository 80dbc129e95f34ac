#include "app/hrpp_options.h"

#include <algorithm>
#include <string>

#include "app/cli_names.h"
#include "app/hrpp_config_file.h"
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

float parse_number(const std::string& v) {
  std::size_t used = 0;
  float x = 0.0f;
  try {
    x = std::stof(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (v.empty() || used != v.size()) throw Error("'" + v + "' is not a number");
  return x;
}

std::uint32_t parse_count(const std::string& v) {
  if (v.empty() || v.size() > 9 || v.find_first_not_of("0123456789") != std::string::npos)
    throw Error("'" + v + "' is not a non-negative integer");
  return static_cast<std::uint32_t>(std::stoul(v));
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
    if (f == "--hrpp-adaptive") o.adaptive = cli.adaptive;
    if (f == "--hrpp-mode") o.mode = cli.mode;
    if (f == "--hrpp-fallback") o.fallback = cli.fallback;
    if (f == "--hrpp-gate") o.gate = cli.gate;
    if (f == "--hash") o.hash = cli.hash;
    if (f == "--hash-bits") o.hash_bits = cli.hash_bits;
    if (f == "--hash-dir-bits") o.hash_dir_bits = cli.hash_dir_bits;
    if (f == "--go-up") o.go_up = cli.go_up;
    if (f == "--go-up-size") o.go_up_size = cli.go_up_size;
    if (f == "--table-preset") {  // the whole table
      o.preset = cli.preset;
      o.sets = cli.sets;
      o.ways = cli.ways;
      o.nodes = cli.nodes;
      o.policy = cli.policy;
    }
    if (f == "--table-sets") o.sets = cli.sets;
    if (f == "--table-ways") o.ways = cli.ways;
    if (f == "--table-nodes") o.nodes = cli.nodes;
    if (f == "--table-policy") o.policy = cli.policy;
    if (f == "--hrpp-batch") o.batch = cli.batch;
    if (f == "--hrpp-pilot") o.pilot = cli.pilot;
    if (f == "--hrpp-serial") o.serial = cli.serial;
    if (f == "--hrpp-count") o.count_baseline = cli.count_baseline;
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
    throw Error("--hrpp-fallback skip: skip lists are the BVH kernels'; in front of the "
                "driver's ray queries use --hrpp-fallback root");
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
    if (policy[k]) t.policy = *policy[k];
  }
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
      throw Error("--hrpp-gate: exact mode already bounds every true positive's trace");
    (void)make_predictor_params(c, k, Aabb{});
    if (c.predicts(k) && query_kind(k) != QueryKind::kAny && is_light_space(c.hash[k].kind))
      throw Error(std::string("--hash: ") + hash_kind_name(c.hash[k].kind) +
                  " keys shadow rays (it reads the ray's end at the light), not " +
                  ray_class_name(k) + " rays");
  }
  return c;
}

// A number as --go-up-size and --hrpp-gate take it: "0.02" (6 digits; no round trip needed).
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
    " (V: every ray class; a list of V and class=V, in order, e.g. hrpp,shadow=light-depth; "
    "classes: camera, bounce, shadow)";

// --hash, --hash-bits, --go-up, --go-up-size: the key of each ray class and what its table stores.
void add_key_options(CLI::App* cmd, HrppOptions& o, const std::string& g) {
  const std::string per_class = kPerClass;
  cmd->add_option_function<std::string>(
         "--hash",
         [&o](const std::string& v) {
           parse_per_class(v, "--hash", o.hash,
                           [](const std::string& n) { return parse_hash_kind(n); });
         },
         "Ray hash: hrpp (the paper's IEEE-754 bits), grid-spherical, two-point; for shadow "
         "rays also light (the light end on a grid, the direction from the light in octahedral "
         "cells) and light-depth (light plus the receiver's distance from the light)" +
             per_class)
      ->default_str(per_class_default(o.hash, [](HashKind k) { return hash_kind_name(k); }))
      ->group(g);
  cmd->add_option_function<std::string>(
         "--hash-bits",
         [&o](const std::string& v) {
           parse_per_class(v, "--hash-bits", o.hash_bits, parse_count);
         },
         "Hash precision N (1..8)" + per_class)
      ->default_str(
          per_class_default(o.hash_bits, [](std::uint32_t n) { return std::to_string(n); }))
      ->group(g);
  cmd->add_option_function<std::string>(
         "--hash-dir-bits",
         [&o](const std::string& v) {
           parse_per_class(v, "--hash-dir-bits", o.hash_dir_bits, parse_count);
         },
         "grid-spherical: precision D (1..8) of the direction bins (0: N, --hash-bits)" +
             per_class)
      ->default_str("0")
      ->group(g);
  cmd->add_option_function<std::string>(
         "--go-up",
         [&o](const std::string& v) { parse_per_class(v, "--go-up", o.go_up, parse_count); },
         "Go-up level: predict the ancestor L levels above the leaf that held the hit" + per_class)
      ->default_str(per_class_default(o.go_up, [](std::uint32_t n) { return std::to_string(n); }))
      ->group(g);
  cmd->add_option_function<std::string>(
         "--go-up-size",
         [&o](const std::string& v) {
           parse_per_class(v, "--go-up-size", o.go_up_size, parse_number);
         },
         "Then go further up while the node's box is smaller than this share (0..1) of the "
         "scene box's largest extent: the same beam width on dense and coarse meshes (0: off)" +
             per_class)
      ->default_str(per_class_default(o.go_up_size, format_number))
      ->group(g);
}

// --table-preset, --table-sets, --table-ways, --table-nodes, --table-policy, per ray class.
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
         "study), tiny (4x2x2 lru)" +
             per_class)
      ->default_str(per_class_default(
          o.preset, [](TablePreset p) { return std::string(name_in(kTablePresetNames, p)); }))
      ->group(g);
  const auto count_option = [&](const char* flag, PerClass<std::uint32_t>& v, const char* what) {
    const std::string name = flag;
    cmd->add_option_function<std::string>(
           name, [&v, name](const std::string& s) { parse_per_class(s, name, v, parse_count); },
           std::string(what) + " (overrides the preset)" + per_class)
        ->group(g);
  };
  count_option("--table-sets", o.sets, "Sets (a power of two)");
  count_option("--table-ways", o.ways, "Ways per set");
  count_option("--table-nodes", o.nodes, "Nodes per entry");
  cmd->add_option_function<std::string>(
         "--table-policy",
         [&o](const std::string& v) {
           parse_per_class(v, "--table-policy", o.policy, [](const std::string& n) {
             return std::optional<TablePolicy>(parse_in(kTablePolicyNames, n, "unknown policy"));
           });
         },
         "When full: none (drop), lru (evict the least recently used) or fifo (evict the "
         "oldest key; probe hits write nothing) (overrides the preset)" +
             per_class)
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
  cmd->add_option_function<Fallback>(
         "--hrpp-fallback", [&o](const Fallback& f) { o.fallback = f; },
         "What a ray its prediction did not answer traces: root (a full traversal, as "
         "the paper) or skip (from the root, not entering the nodes its prediction "
         "tested: the same answer, the verification not paid twice; the BVH kernels only)")
      ->transform(one_of(kFallbackNames))
      ->default_str("skip; root with --tracer rayquery")
      ->group(g);
  cmd->add_option_function<std::string>(
         "--hrpp-gate",
         [&o](const std::string& v) { parse_per_class(v, "--hrpp-gate", o.gate, parse_number); },
         "Distance gate G, speculative mode: accept a predicted closest hit only within G times "
         "the nearest hit that traced rays of its key found; a farther one bounds a full "
         "traversal (fewer wrong closest hits; hit-all classes, 0: off)" +
             std::string(kPerClass))
      ->default_str("0")
      ->group(g);
  add_key_options(cmd, o, g);
  add_table_options(cmd, o, g);
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
  cmd->add_option("--hrpp-config", o.config_file,
                  "HRPP's settings from FILE.json: the \"hrpp\" object of a --stats JSON (or "
                  "that JSON itself) or any part of it (docs/HRPP.md, \"Settings file\"); "
                  "flags given here override it")
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
