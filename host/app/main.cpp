// hrpp: headless GPU path tracer with Hash-Based Ray Path Prediction. main() only dispatches;
// errors the user can fix end here as one line on stderr and exit status 1.
#include <cstdio>
#include <exception>

#include "app/commands.h"
#include "common/error.h"

int main(int argc, char** argv) {
  CLI::App app{"hrpp: GPU path tracer with Hash-Based Ray Path Prediction (HRPP)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "hrpp 0.1.0");
  hrpp::app::add_scene_command(app);
  hrpp::app::add_trace_command(app);
  hrpp::app::add_bench_command(app);
  hrpp::app::add_render_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const hrpp::Error& e) {
    std::fprintf(stderr, "hrpp: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
