#pragma once
// Errors thrown by gather_core. Every message starts with the file (or the
// input) it is about, so a CLI or node can print it as one line and exit 2.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gather {

class Error : public std::runtime_error {
 public:
  // `where` is a file path or an input name ("--source"); `what` says what is wrong.
  Error(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

// A failure while running (not bad input): a process that stopped
// answering, a mission that did not finish, a broken invariant. The CLI and
// nodes exit 1 on it (2 is for bad input).
class RuntimeError : public Error {
 public:
  using Error::Error;
};

// A numeric input must be finite and in [lo, hi] (`open_lo` / `open_hi`
// make that end exclusive); otherwise throws Error(where, "<key> = <v> must
// be in [lo, hi]<unit>"). The one range check of scenarios, partition
// parameters and planner options.
inline void require_in_range(double v, double lo, double hi, const std::string& where, const std::string& key,
                             const char* unit = "", bool open_lo = false, bool open_hi = false) {
  if (std::isfinite(v) && (open_lo ? v > lo : v >= lo) && (open_hi ? v < hi : v <= hi)) return;
  std::ostringstream s;
  s << key << " = " << v << " must be in " << (open_lo ? "(" : "[") << lo << ", " << hi << (open_hi ? ")" : "]")
    << unit;
  throw Error(where, s.str());
}

}  // namespace gather
