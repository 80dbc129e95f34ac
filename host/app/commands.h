// The CLI's subcommands: each registers its options on the CLI11 app and runs from an options
// struct, so main() only dispatches.
#pragma once

#include <CLI/CLI.hpp>

namespace hrpp::app {

void add_scene_command(CLI::App& app);
void add_trace_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_render_command(CLI::App& app);

}  // namespace hrpp::app
