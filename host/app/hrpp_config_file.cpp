#include "app/hrpp_config_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <string_view>

#include "common/error.h"
#include "hrpp/ray_hash.h"

namespace hrpp::app {
namespace {

using nlohmann::json;

// The figures a --stats JSON writes beside the configuration: read past.
constexpr std::array<std::string_view, 9> kFigureKeys = {"camera",
                                                         "bounce",
                                                         "shadow",
                                                         "hit_any",
                                                         "hit_all",
                                                         "summary",
                                                         "answered_without_trace",
                                                         "traced_with_shorter_tmax",
                                                         "rays"};
// The summaries of "keys" a --stats JSON writes: checked against what "keys" sets.
constexpr std::array<std::string_view, 11> kSummaryKeys = {
    "hash",        "hash_bits",    "gate",        "go_up",    "go_up_size", "table_sets",
    "table_ways",  "table_nodes",  "table_policy", "table_bytes", "sm_tables"};

bool is_in(std::string_view key, std::span<const std::string_view> keys) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// Reads one key's value, its errors naming the file and the key.
class Reader {
 public:
  Reader(const std::string& path, std::string key) : path_(path), key_(std::move(key)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path_ + ": " + key_ + ": " + what);
  }
  bool boolean(const json& v) const {
    if (!v.is_boolean()) fail("must be true or false");
    return v.get<bool>();
  }
  std::uint32_t count(const json& v) const {
    if (!v.is_number_unsigned() || v.get<std::uint64_t>() > 0xFFFFFFFFu)
      fail("must be a non-negative integer");
    return static_cast<std::uint32_t>(v.get<std::uint64_t>());
  }
  float number(const json& v) const {
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail("must be a finite number");
    return static_cast<float>(v.get<double>());
  }
  template <class E, std::size_t N>
  E name(const json& v, const NameTable<E, N>& table) const {
    if (!v.is_string()) fail("must be one of " + names_in(table));
    try {
      return parse_in(table, v.get<std::string>(), "unknown value");
    } catch (const Error& e) {
      fail(e.what());
    }
  }

 private:
  const std::string& path_;
  std::string key_;
};

// keys.<class>: the class's key, go-up rule and table into `o`.
void read_class(const json& j, const std::string& path, RayClass c, HrppOptions& o) {
  const std::string prefix = std::string("keys.") + ray_class_name(c);
  if (!j.is_object()) Reader(path, prefix).fail("must be an object");
  for (const auto& [key, v] : j.items()) {
    const Reader r(path, prefix + "." + key);
    if (key == "hash")
      o.hash[c] = r.name(v, kHashKindNames);
    else if (key == "hash_bits")
      o.hash_bits[c] = r.count(v);
    else if (key == "hash_dir_bits")
      o.hash_dir_bits[c] = r.count(v);
    else if (key == "gate")
      o.gate[c] = r.number(v);
    else if (key == "go_up")
      o.go_up[c] = r.count(v);
    else if (key == "go_up_size")
      o.go_up_size[c] = r.number(v);
    else if (key == "table_preset")
      o.preset[c] = r.name(v, kTablePresetNames);
    else if (key == "table_sets")
      o.sets[c] = r.count(v);
    else if (key == "table_ways")
      o.ways[c] = r.count(v);
    else if (key == "table_nodes")
      o.nodes[c] = r.count(v);
    else if (key == "table_policy")
      o.policy[c] = r.name(v, kTablePolicyNames);
    else if (key == "sm_tables")
      o.sm_tables[c] = r.count(v);
    else if (key != "table_bytes")
      r.fail(
          "unknown key (hash, hash_bits, hash_dir_bits, gate, go_up, go_up_size, "
          "table_preset, table_sets, table_ways, table_nodes, table_policy, sm_tables)");
  }
}

PerClass<bool> read_classes(const json& v, const Reader& r) {
  if (!v.is_array()) r.fail("must be a list of " + names_in(kRayClassNames));
  PerClass<bool> on{};
  for (const json& name : v) on[r.name(name, kRayClassNames)] = true;
  return on;
}

// The top level's configuration keys into `o`; false for a key that is not one.
bool read_top(const std::string& key, const json& v, const Reader& r, HrppOptions& o) {
  if (key == "enabled")
    o.enabled = r.boolean(v);
  else if (key == "mode")
    o.mode = r.name(v, kPredictorModeNames);
  else if (key == "fallback")
    o.fallback = r.name(v, kFallbackNames);
  else if (key == "ray_classes")
    o.classes = read_classes(v, r);
  else if (key == "adaptive")
    o.adaptive = r.boolean(v);
  else if (key == "count_baseline")
    o.count_baseline = r.boolean(v);
  else if (key == "batch")
    o.batch = r.count(v);
  else if (key == "pilot")
    o.pilot = r.count(v);
  else if (key == "serial")
    o.serial = r.boolean(v);
  else
    return false;
  return true;
}

// The configuration object: a --stats JSON's "hrpp_predictor" (render) or "hrpp" (trace,
// bench) object, or the file's top level.
const json& configuration(const json& file) {
  for (const char* k : {"hrpp_predictor", "hrpp"})
    if (file.is_object() && file.contains(k) && file[k].is_object()) return file[k];
  return file;
}

// Equal as the configuration stores them (numbers as float).
bool same_value(const json& a, const json& b) {
  if (a.is_number() && b.is_number())
    return static_cast<float>(a.get<double>()) == static_cast<float>(b.get<double>());
  return a == b;
}

}  // namespace

PredictorConfig config_with_file(const HrppOptions& cli, DeviceTracerKind tracer) {
  const std::string& path = cli.config_file;
  const nlohmann::json file = read_hrpp_config(path);
  const HrppOptions from_file = options_from_file(file, path, HrppOptions{});
  // The file checked as if HRPP were on, whatever its "enabled" says: its keys are for then.
  HrppOptions on = from_file;
  on.enabled = true;
  PredictorConfig file_only;
  try {
    file_only = on.build(tracer);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  check_file_agrees(file, path, file_only);
  try {
    return from_file.overridden_by(cli).build(tracer);
  } catch (const Error& e) {  // a flag against the file's settings
    throw Error(path + " with the flags: " + e.what());
  }
}

nlohmann::json read_hrpp_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the --hrpp-config file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + ": not JSON (" + e.what() + ")");
  }
}

HrppOptions options_from_file(const nlohmann::json& file, const std::string& path,
                              const HrppOptions& defaults) {
  const json& cfg = configuration(file);
  if (!cfg.is_object()) throw Error(path + ": the HRPP configuration must be a JSON object");
  HrppOptions o = defaults;
  for (const auto& [key, v] : cfg.items()) {
    const Reader r(path, key);
    if (read_top(key, v, r, o) || is_in(key, kFigureKeys) || is_in(key, kSummaryKeys)) continue;
    if (key != "keys")
      r.fail(
          "unknown key (enabled, mode, fallback, ray_classes, adaptive, count_baseline, "
          "batch, pilot, serial, keys)");
    if (!v.is_object()) r.fail("must be an object of camera, bounce, shadow");
    for (const auto& [name, cls] : v.items())
      read_class(cls, path, Reader(path, "keys." + name).name(json(name), kRayClassNames), o);
  }
  return o;
}

void check_file_agrees(const nlohmann::json& file, const std::string& path,
                       const PredictorConfig& effective) {
  const json& cfg = configuration(file);
  const json runs = predictor_config_json(effective);
  const auto check = [&](const std::string& key, const json& given, const json& used) {
    if (!same_value(given, used))
      throw Error(path + ": " + key + " is " + given.dump() + ", but the predictor runs with " +
                  used.dump() +
                  " (a value without effect, or a summary that disagrees with "
                  "\"keys\")");
  };
  for (const auto& [key, v] : cfg.items()) {
    if (key == "keys") {
      for (const auto& [name, cls] : v.items())
        for (const auto& [k, value] : cls.items())
          if (k != "table_preset") check("keys." + name + "." + k, value, runs["keys"][name][k]);
    } else if (key != "enabled" && !is_in(key, kFigureKeys) && runs.contains(key)) {
      check(key, v, runs[key]);
    }
  }
}

}  // namespace hrpp::app
