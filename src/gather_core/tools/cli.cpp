#include "cli.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "gather_core/input_file.hpp"

namespace gather {
namespace cli {

Args::Args(int argc, char** argv, int first, const std::vector<std::string>& value_flags,
           const std::vector<std::string>& switches) {
  auto known = [](const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
  };
  for (int i = first; i < argc; ++i) {
    std::string a = argv[i];
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string value;
      bool inline_value = false;
      const auto eq = a.find('=');
      if (eq != std::string::npos) {
        value = a.substr(eq + 1);
        a = a.substr(0, eq);
        inline_value = true;
      }
      if (known(switches, a)) {
        if (inline_value) throw UsageError(a + " takes no value");
        switches_[a] = true;
      } else if (known(value_flags, a)) {
        if (!inline_value) {
          if (i + 1 >= argc) throw UsageError(a + " needs a value");
          value = argv[++i];
        }
        values_[a].push_back(value);
      } else {
        throw UsageError("unknown option " + quote_input(a, 40));
      }
    } else {
      positional_.push_back(a);
    }
  }
}

std::string Args::get(const std::string& flag, const std::string& fallback) const {
  auto it = values_.find(flag);
  return it == values_.end() ? fallback : it->second.back();
}

std::vector<std::string> Args::all(const std::string& flag) const {
  auto it = values_.find(flag);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

int Args::get_int(range::Id id, int fallback) const {
  const InputRange& r = input_range(id);
  if (!has(r.key)) return fallback;
  const std::string s = get(r.key);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0')
    throw UsageError(std::string(r.key) + " expects an integer, got '" + quote_input(s, 40) + "'");
  if (errno != 0 || !r.accepts(static_cast<double>(v)))
    throw UsageError(std::string(r.key) + " must be in " + r.text() + ", got '" + quote_input(s, 40) + "'");
  return static_cast<int>(v);
}

double Args::get_double(range::Id id, double fallback) const {
  const InputRange& r = input_range(id);
  if (!has(r.key)) return fallback;
  const std::string s = get(r.key);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0')
    throw UsageError(std::string(r.key) + " expects a number, got '" + quote_input(s, 40) + "'");
  if (!r.accepts(v))
    throw UsageError(std::string(r.key) + " must be a finite value in " + r.text() + ", got '" + quote_input(s, 40) +
                     "'");
  return v;
}

}  // namespace cli
}  // namespace gather
