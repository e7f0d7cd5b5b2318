#pragma once
// `sinew profile STATS`: order statistics per stage of the stats JSON that `sinew run
// --stats` writes, as a table, and optionally as CSV and a PNG chart (tools/plot/).
namespace sinew::cli {
int profile_command(int argc, char** argv);
}
