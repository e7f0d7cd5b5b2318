// The command-line option parser (tools/cli_options.hpp): positional counts, optional
// trailing arguments, and integers checked against their minimum.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "tools/cli_options.hpp"

using namespace sinew::cli;

namespace {

// parse() on a program name and `args`.
bool parse(Options& options, std::vector<std::string> args) {
  args.insert(args.begin(), "program");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  return options.parse(static_cast<int>(argv.size()) - 1, argv.data() + 1);
}

}  // namespace

TEST_CASE("cli options: optional trailing arguments between the minimum and maximum count") {
  for (const int count : {0, 1, 2}) {
    Options options("p [A] [B]", "test", {}, 0, 2);
    std::vector<std::string> args(count, "x");
    CHECK(parse(options, args));
    CHECK(options.positional().size() == static_cast<size_t>(count));
  }
  Options too_many("p [A] [B]", "test", {}, 0, 2);
  CHECK_THROWS_AS(parse(too_many, {"a", "b", "c"}), UsageError);
  // Without a maximum the count is exact, as before.
  Options exact("p A", "test", {}, 1);
  CHECK_THROWS_AS(parse(exact, {}), UsageError);
  Options exact_two("p A", "test", {}, 1);
  CHECK_THROWS_AS(parse(exact_two, {"a", "b"}), UsageError);
  Options exact_one("p A", "test", {}, 1);
  CHECK(parse(exact_one, {"a"}));
}

TEST_CASE("cli options: integers are whole, in range, or a usage error naming what was read") {
  CHECK(parse_int("120", "FRAMES", 1) == 120);
  CHECK(parse_int("-3", "X", -5) == -3);
  for (const char* bad : {"0", "abc", "12x", "", "1.5", "99999999999"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(parse_int(bad, "FRAMES", 1), UsageError);
  }
  try {
    parse_int("abc", "FRAMES", 1);
  } catch (const UsageError& e) {
    CHECK(std::string(e.what()) == "FRAMES expects an integer >= 1, got 'abc'");
  }
  Options options("p", "test", {{"--steps", "N", "steps"}}, 0);
  CHECK(parse(options, {"--steps", "7"}));
  CHECK(options.get_int("--steps", 1, 1) == 7);
  CHECK(options.get_int("--absent", 4, 1) == 4);
  Options bad("p", "test", {{"--steps", "N", "steps"}}, 0);
  CHECK(parse(bad, {"--steps", "0"}));
  CHECK_THROWS_AS(bad.get_int("--steps", 1, 1), UsageError);
}
