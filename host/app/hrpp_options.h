// The HRPP option group, one definition for every command that traces (trace, bench, render):
// --hrpp, --hrpp-rays, --hrpp-mode, --table-preset and --hrpp-config, the settings file that
// holds every other setting (app/hrpp_config_file.h); and the JSON form of the configuration
// and of a run's predictor figures.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "gpu/device_tracer_kind.h"
#include "hrpp/predictor_config.h"
#include "hrpp/predictor_stats.h"

namespace hrpp::app {

// The settings, from the flags (parsed once, by CLI11 transformers and callbacks, into the enums
// they stand for: names from the enums' name tables) and the --hrpp-config file (its keys named
// beside each field); config() combines the preset with its overrides.
struct HrppOptions {
  bool enabled = false;             // --hrpp off | on
  PerClass<bool> classes{{true, true, true}};  // --hrpp-rays: the classes that predict
  bool adaptive = true;             // adaptive
  PredictorMode mode = PredictorMode::kSpeculative;
  // fallback; unset: skip in front of the BVH kernels, root in front of the driver's ray
  // queries (skip lists are the BVH kernels').
  std::optional<Fallback> fallback;
  // Per ray class (keys.<class>.hash, hash_bits, hash_dir_bits, go_up, go_up_size): the
  // --hrpp on default per class, measured in results/KEYS.md:
  // camera rays the paper's key; bounce rays grid-spherical at N = 6 (the finest measured that
  // kept every stand-in's relMSE against HRPP off at most 1e-3); shadow rays
  // light-depth at N = 6 storing the subtree of at least 2% of the scene's extent above the
  // occluder's leaf, four per entry (the beam table).
  PerClass<HashKind> hash{{HashKind::kIeee, HashKind::kGridSpherical, HashKind::kLightDepth}};
  PerClass<std::uint32_t> hash_bits{{6, 6, 6}};
  PerClass<std::uint32_t> hash_dir_bits{};  // grid-spherical direction bins (0: hash_bits)
  PerClass<std::uint32_t> go_up{{0, 0, 0}};
  PerClass<float> go_up_size{{0.0f, 0.0f, 0.02f}};
  // Table per ray class (--table-preset takes V for every class or a list of V and class=V;
  // keys.<class>.table_preset, table_sets, table_ways, table_nodes, table_policy, sm_tables).
  PerClass<TablePreset> preset{{TablePreset::kTuned, TablePreset::kTuned, TablePreset::kBeam}};
  PerClass<std::uint32_t> sets{}, ways{}, nodes{}, sm_tables{};  // 0: the preset's
  PerClass<std::optional<TablePolicy>> policy{};    // none: the preset's
  PerClass<float> gate{};  // keys.<class>.gate (PredictorConfig::gate; hit-all classes)
  std::uint32_t batch = 0;
  std::uint32_t pilot = PredictorConfig{}.pilot;
  bool serial = false;
  bool count_baseline = false;
  std::string config_file;         // --hrpp-config FILE.json (app/hrpp_config_file.h)
  std::vector<std::string> given;  // the HRPP flags given on the command line

  // The predictor configuration (enabled = --hrpp on) in front of `tracer`: with --hrpp-config,
  // the file's, each flag given on the command line overriding what it sets (--table-preset the
  // whole table). Throws hrpp::Error naming the flag, or the file and the key.
  PredictorConfig config(DeviceTracerKind tracer = DeviceTracerKind::kCompute) const;

  // The configuration these options set, the file aside.
  PredictorConfig build(DeviceTracerKind tracer) const;
  // These options with the fields of the flags `cli` was given replaced by its own.
  HrppOptions overridden_by(const HrppOptions& cli) const;
};

// --hrpp-rays: a comma-separated subset of camera, bounce, shadow; the older names all (camera,
// bounce: the hit-all rays), any (shadow) and both (every class) still work. Throws hrpp::Error
// naming the flag.
PerClass<bool> parse_ray_classes(const std::string& list);
// "camera,bounce,shadow": the classes that are on, in class order.
std::string ray_class_list(const PerClass<bool>& classes);

// Adds the options to `cmd` in an "HRPP" group.
void add_hrpp_options(CLI::App* cmd, HrppOptions& o);

nlohmann::json predictor_config_json(const PredictorConfig& config);
nlohmann::json predictor_summary_json(const PredictorSummary& s);

}  // namespace hrpp::app
