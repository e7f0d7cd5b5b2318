#pragma once
// A small command-line option parser: declared options with help text, so that --help
// and the parser can never disagree.
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sinew::cli {

struct OptionSpec {
  std::string name;       // "--frames"
  std::string value;      // "N" ("" for a flag)
  std::string help;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `text` as an integer of at least `min_value`; else UsageError naming `what`.
int parse_int(const std::string& text, const std::string& what, int min_value);
// `text` as a finite number >= 0 (a tolerance that 0 turns off); else UsageError naming `what`.
double parse_nonnegative(const std::string& text, const std::string& what);

class Options {
 public:
  // `positional` arguments, or from `positional` to `max_positional` of them when that is
  // larger (optional trailing arguments).
  Options(std::string usage, std::string summary, std::vector<OptionSpec> specs, int positional,
          int max_positional = -1);
  // Throws UsageError; returns false if --help was given (help already printed).
  bool parse(int argc, char** argv);
  std::string help() const;

  bool has(const std::string& name) const { return m_values.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  int get_int(const std::string& name, int fallback, int min_value) const;
  double get_double(const std::string& name, double fallback, double min_exclusive) const;
  // parse_nonnegative of the option's value.
  double get_nonnegative(const std::string& name, double fallback) const;
  // The value of option `name`, which must be one of `allowed` (UsageError naming both
  // otherwise); "" when not given.
  std::string get_one_of(const std::string& name, const std::vector<std::string>& allowed) const;
  const std::vector<std::string>& positional() const { return m_positional; }

 private:
  std::string m_usage, m_summary;
  std::vector<OptionSpec> m_specs;
  int m_positional_count, m_max_positional;
  std::map<std::string, std::string> m_values;
  std::vector<std::string> m_positional;
};

}  // namespace sinew::cli
