// `sinew session SCRIPT`: a scripted interaction session (ui/): the scene drawn off-screen
// with the panel, driven by the script's synthetic input; expectations decide the exit code.
#include <cstdio>
#include <iostream>

#include "tools/cli_commands.hpp"
#include "tools/cli_options.hpp"
#include "ui/session_runner.hpp"

namespace sinew::cli {

int session_command(int argc, char** argv) {
  Options options("sinew session SCRIPT [options]",
                  "Runs a session script (JSON, see docs/sessions.md): its scene frame by frame, drawn\n"
                  "off-screen (EGL) with the control panel, the script's pointer, key, grab, camera and\n"
                  "parameter events applied at their frames, screenshots taken and expectations checked.\n"
                  "Deterministic: the same script gives the same frames and the same final state hash.",
                  {{"--record", "OUT.mp4", "record the whole session as a video (ffmpeg in PATH); the\n"
                                           "                          script's record_start/record_stop and key 'c' also use it"},
                   {"--threads", "T", "worker threads (default: all cores); results do not depend on T"},
                   {"--quiet", "", "no progress lines; the event log and the summary still print"}},
                  1);
  if (!options.parse(argc, argv)) return 0;
  const SessionScript script = load_session(options.positional()[0]);
  SessionOptions run;
  run.record_path = options.get("--record");
  run.threads = options.get_int("--threads", 0, 1);
  run.progress = !options.has("--quiet");
  const SessionResult result = run_session(script, run, std::cout);
  std::printf("session %s: %d frames, %d expectations, %d failed, state hash %016llx%s\n", script.name.c_str(),
              result.frames, result.expectations, result.failed, static_cast<unsigned long long>(result.state_hash),
              result.finite ? "" : ", stopped: the simulation failed");
  if (!result.finite) return 3;
  return result.failed > 0 ? 4 : 0;
}

}  // namespace sinew::cli
