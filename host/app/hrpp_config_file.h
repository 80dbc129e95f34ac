// HRPP's experiment settings in a file (--hrpp-config FILE.json). The file takes the form of the
// "hrpp" object of a --stats JSON (predictor_config_json, app/hrpp_options.h), so a run's
// stats re-run its predictor: the file may be that stats JSON itself (its "hrpp" object is read,
// the figures beside the configuration are left alone) or any part of the object, the rest at
// the defaults:
//   enabled, mode, fallback, ray_classes (a list), adaptive, count_baseline, batch, pilot,
//   serial, and keys: {camera | bounce | shadow: {hash, hash_bits, hash_dir_bits, gate, go_up,
//   go_up_size, table_preset, table_sets, table_ways, table_nodes, table_policy, sm_tables}}
// with the summaries a --stats JSON adds (the top-level hash, hash_bits, gate, go_up,
// go_up_size, table_*, sm_tables and keys.*.table_bytes), which must agree with what the rest
// sets. This is the one place that validates it: an unknown key, a value of the wrong type or
// name, or a value the predictor would not run with (one that has no effect, or a summary that
// disagrees) is one line naming the file and the key.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "app/hrpp_options.h"

namespace hrpp::app {

// HrppOptions::config with --hrpp-config: the file's configuration (validated on its own), then
// the flags `cli` was given over it.
PredictorConfig config_with_file(const HrppOptions& cli, DeviceTracerKind tracer);

// The options `file` (the parsed JSON of `path`) sets, over `defaults`. Throws hrpp::Error
// naming `path` and the key.
HrppOptions options_from_file(const nlohmann::json& file, const std::string& path,
                              const HrppOptions& defaults);

// Reads `path` (hrpp::Error naming it when it cannot be read or parsed as JSON).
nlohmann::json read_hrpp_config(const std::string& path);

// Throws hrpp::Error naming `path` and the first key of `file` whose value differs from the one
// `effective` (the configuration the file alone sets) runs with.
void check_file_agrees(const nlohmann::json& file, const std::string& path,
                       const PredictorConfig& effective);

}  // namespace hrpp::app
