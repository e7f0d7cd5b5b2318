#pragma once
// The `sinew` subcommands; each parses its own options and returns the exit code.
namespace sinew::cli {
int run_command(int argc, char** argv);
int session_command(int argc, char** argv);
}
