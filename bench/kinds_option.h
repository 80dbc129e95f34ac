// The --kinds option of the GPU benches (bench_ray_order, bench_sbvh): batch kinds by the names
// of host/trace/ray_batches.h (ray_kind_named), so every name the option lets through is a kind.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "trace/ray_batches.h"

namespace hrpp::bench {

inline void add_kinds_option(CLI::App& app, std::vector<std::string>& kinds) {
  app.add_option("--kinds", kinds, "Batch kinds: primary, ao, diffuse")
      ->delimiter(',')
      ->check([](const std::string& s) {
        return ray_kind_named(s) ? std::string() : "unknown kind '" + s + "' (primary, ao, diffuse)";
      })
      ->capture_default_str();
}

}  // namespace hrpp::bench
