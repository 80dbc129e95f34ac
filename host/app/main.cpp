// hrpp: headless GPU path tracer with Hash-Based Ray Path Prediction. main() only dispatches;
// errors the user can fix end here as one line on stderr and exit status 1.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "app/commands.h"
#include "app/provenance.h"
#include "common/error.h"
#include "common/interrupt.h"

int main(int argc, char** argv) {
  CLI::App app{"hrpp: GPU path tracer with Hash-Based Ray Path Prediction (HRPP)"};
  app.require_subcommand(1);
  hrpp::app::set_command_line(argc, argv);
  app.set_version_flag("--version", "hrpp commit " + std::string(hrpp::app::build_commit()));
  hrpp::app::add_scene_command(app);
  hrpp::app::add_trace_command(app);
  hrpp::app::add_bench_command(app);
  hrpp::app::add_render_command(app);
  if (argc >= 2 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "hrpp: error: unknown command \"%s\" (commands: %s)\n", argv[1],
                   names.c_str());
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed; any other parse error is one line naming the
    // option (CLI11 would add a "Run with --help" line and exit with its own codes).
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::fprintf(stderr, "hrpp: error: %s (see --help)\n", e.what());
    return 1;
  } catch (const hrpp::Error& e) {
    std::fprintf(stderr, "hrpp: error: %s\n", e.what());
    return 1;
  } catch (const hrpp::Interrupted& i) {  // the outputs of the passes done are written
    return 128 + i.signal;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "hrpp: error: out of host memory (the scene or the image is too big for "
                         "this machine)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
