// `sinew session` as a user meets it: a failed expectation is exit code 4, a malformed
// script exit code 2 with the event's JSON path, and a good script exit code 0.
#include <doctest/doctest.h>

#include <string>

#include "tests/support/cli_runner.hpp"

using sinew::test::run_sinew;
using sinew::test::TempDir;

namespace {

std::string script(const std::string& events) {
  return std::string(R"({"scene": ")") + SINEW_SOURCE_DIR + R"(/assets/scenes/paper000_beam_150kPa.json",
    "frames": 10, "size": [640, 480], "events": [)" + events + "]}";
}

}  // namespace

TEST_CASE("sinew session: expectations decide the exit code") {
  TempDir dir("session");
  const auto ok = run_sinew("session --quiet --threads 1 " +
                            dir.write("ok.json", script(R"({"frame": 10, "do": "expect", "quantity": "t", "above": 0.1})")));
  INFO(ok.output);
  CHECK(ok.code == 0);
  CHECK(ok.output.find("1 expectations, 0 failed") != std::string::npos);
  const auto failed = run_sinew("session --quiet --threads 1 " +
                                dir.write("bad.json", script(R"({"frame": 10, "do": "expect", "quantity": "t", "below": 0.1})")));
  INFO(failed.output);
  CHECK(failed.code == 4);
  CHECK(failed.output.find("expect t = 0.166") != std::string::npos);
  CHECK(failed.output.find("FAILED (events[0])") != std::string::npos);
}

TEST_CASE("sinew session: a malformed script is exit code 2 naming the event") {
  TempDir dir("session");
  const std::string path = dir.write("bad.json", script(R"({"frame": 1, "do": "grab"})"));
  const auto r = run_sinew("session " + path);
  INFO(r.output);
  CHECK(r.code == 2);
  CHECK(r.output.find(path + ": events[0]: expected exactly one of \"pixel\" and \"point\"") != std::string::npos);
}
