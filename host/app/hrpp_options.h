// The HRPP option group, one definition for every command that traces (trace, bench, render):
// --hrpp, --hrpp-rays, --hrpp-adaptive, --hrpp-mode, --hash, --hash-bits, --go-up, --table-*,
// --hrpp-batch, --hrpp-serial; and the JSON form of the configuration and of a run's predictor
// figures.
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "hrpp/predictor_config.h"
#include "hrpp/predictor_stats.h"

namespace hrpp::app {

// Flags are parsed once, by CLI11 transformers, into the enums and flags they stand for; only
// the ray-class list and the table preset and policy (which default to the preset's) are
// resolved in config().
struct HrppOptions {
  bool enabled = false;             // --hrpp off | on
  std::string rays = "camera,bounce,shadow";  // ray classes that predict (or all | any | both)
  bool adaptive = true;             // --hrpp-adaptive on | off
  PredictorMode mode = PredictorMode::kSpeculative;
  HashKind hash = HashKind::kIeee;
  std::uint32_t hash_bits = 6;
  std::uint32_t go_up = 0;
  std::string preset = "tuned";
  std::uint32_t sets = 0, ways = 0, nodes = 0;  // 0: the preset's
  std::string policy;                           // "": the preset's
  std::uint32_t batch = 0;
  std::uint32_t pilot = PredictorConfig{}.pilot;
  bool serial = false;
  bool count_baseline = false;

  // The predictor configuration (enabled = --hrpp on). Throws hrpp::Error naming the flag.
  // --hrpp-rays: a comma-separated subset of camera, bounce, shadow; the older names all
  // (camera, bounce: the hit-all rays), any (shadow) and both (every class) still work.
  PredictorConfig config() const;
};

// Adds the options to `cmd` in an "HRPP" group.
void add_hrpp_options(CLI::App* cmd, HrppOptions& o);

nlohmann::json predictor_config_json(const PredictorConfig& config);
nlohmann::json predictor_summary_json(const PredictorSummary& s);

}  // namespace hrpp::app
