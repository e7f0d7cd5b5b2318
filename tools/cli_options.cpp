#include "tools/cli_options.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace sinew::cli {

int parse_int(const std::string& text, const std::string& what, int min_value) {
  int value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size() || value < min_value)
    throw UsageError(what + " expects an integer >= " + std::to_string(min_value) + ", got '" + text + "'");
  return value;
}

double parse_nonnegative(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value) || value < 0)
    throw UsageError(what + " expects a number >= 0, got '" + text + "'");
  return value;
}

Options::Options(std::string usage, std::string summary, std::vector<OptionSpec> specs, int positional,
                 int max_positional)
    : m_usage(std::move(usage)), m_summary(std::move(summary)), m_specs(std::move(specs)),
      m_positional_count(positional), m_max_positional(std::max(positional, max_positional)) {}

std::string Options::help() const {
  std::ostringstream out;
  out << "usage: " << m_usage << "\n\n" << m_summary << "\n\noptions:\n";
  const auto line = [&](std::string left, const std::string& help) {
    if (left.size() < 26) left.resize(26, ' ');
    else left += "\n" + std::string(26, ' ');
    out << left << help << "\n";
  };
  for (const OptionSpec& s : m_specs) line("  " + s.name + (s.value.empty() ? "" : " " + s.value), s.help);
  line("  -h, --help", "show this help");
  return out.str();
}

bool Options::parse(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::fputs(help().c_str(), stdout);
      return false;
    }
    if (arg.rfind("--", 0) != 0) {
      m_positional.push_back(arg);
      continue;
    }
    std::string name = arg, value;
    const auto eq = arg.find('=');
    if (eq != std::string::npos) name = arg.substr(0, eq), value = arg.substr(eq + 1);
    const OptionSpec* spec = nullptr;
    for (const OptionSpec& s : m_specs)
      if (s.name == name) spec = &s;
    if (!spec) throw UsageError("unknown option '" + name + "' (see --help)");
    if (!spec->value.empty() && eq == std::string::npos) {
      if (i + 1 >= argc) throw UsageError("option " + name + " expects a value " + spec->value);
      value = argv[++i];
    }
    if (spec->value.empty() && eq != std::string::npos)
      throw UsageError("option " + name + " takes no value");
    m_values[name] = value;
  }
  const int count = static_cast<int>(m_positional.size());
  if (count < m_positional_count || count > m_max_positional)
    throw UsageError("expected " + std::to_string(m_positional_count) +
                     (m_max_positional > m_positional_count ? " to " + std::to_string(m_max_positional) : "") +
                     " argument(s), got " + std::to_string(count) + " (see --help)");
  return true;
}

std::string Options::get(const std::string& name, const std::string& fallback) const {
  const auto it = m_values.find(name);
  return it == m_values.end() ? fallback : it->second;
}

std::string Options::get_one_of(const std::string& name, const std::vector<std::string>& allowed) const {
  if (!has(name)) return "";
  const std::string value = get(name);
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
  std::string expected;
  for (const std::string& a : allowed) expected += (expected.empty() ? "" : " or ") + a;
  throw UsageError("option " + name + " expects " + expected + ", got '" + value + "'");
}

int Options::get_int(const std::string& name, int fallback, int min_value) const {
  return has(name) ? parse_int(get(name), "option " + name, min_value) : fallback;
}

double Options::get_double(const std::string& name, double fallback, double min_exclusive) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value) || value <= min_exclusive)
    throw UsageError("option " + name + " expects a number > " + std::to_string(min_exclusive) +
                     ", got '" + text + "'");
  return value;
}

double Options::get_nonnegative(const std::string& name, double fallback) const {
  return has(name) ? parse_nonnegative(get(name), "option " + name) : fallback;
}

}  // namespace sinew::cli
