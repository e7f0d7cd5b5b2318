// The `sinew` command: dispatches to subcommands and turns errors into exit codes
// (2: bad usage or input, 3: the simulation failed, 1: anything else).
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "engine/core/error.hpp"
#include "tools/cli_commands.hpp"
#include "tools/cli_options.hpp"
#include "tools/cli_profile.hpp"

namespace {

const char* kHelp =
    "sinew: real-time nonlinear soft bodies (FEM with energy and strain limits, hyperelasticity)\n"
    "\n"
    "usage: sinew COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  run SCENE      simulate a scene headless; progress, per-stage timings, exports\n"
    "  session SCRIPT a scripted interaction session: panel, synthetic input, expectations\n"
    "  profile STATS  per-stage median/p95/p99/max of a run's --stats file; CSV, PNG chart\n"
    "  help           this text\n"
    "\n"
    "Run `sinew COMMAND --help` for the options of a command. Scenes: docs/scenes.md.\n"
    "Exit codes: 0 success, 1 internal error, 2 bad usage or input, 3 simulation failed,\n"
    "4 a session expectation failed.\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "help") || !std::strcmp(argv[1], "--help") ||
      !std::strcmp(argv[1], "-h")) {
    std::fputs(kHelp, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  try {
    if (command == "run") return sinew::cli::run_command(argc - 2, argv + 2);
    if (command == "session") return sinew::cli::session_command(argc - 2, argv + 2);
    if (command == "profile") return sinew::cli::profile_command(argc - 2, argv + 2);
    std::fprintf(stderr, "sinew: unknown command '%s' (see sinew --help)\n", command.c_str());
    return 2;
  } catch (const sinew::cli::UsageError& e) {
    std::fprintf(stderr, "sinew %s: %s\n", command.c_str(), e.what());
    return 2;
  } catch (const sinew::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
