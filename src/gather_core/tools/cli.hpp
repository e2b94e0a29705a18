#pragma once
// Small command-line layer shared by the `gather` subcommands: flags are
// declared up front, anything else is an error naming the flag.
#include <map>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/input_ranges.hpp"

namespace gather {
namespace cli {

// Thrown for a bad command line; main() prints it with the usage hint, exit 2.
struct UsageError : Error {
  explicit UsageError(const std::string& what) : Error("", what) {}
};

class Args {
 public:
  // `value_flags` take a value (--out DIR or --out=DIR), `switches` do not.
  Args(int argc, char** argv, int first, const std::vector<std::string>& value_flags,
       const std::vector<std::string>& switches);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& flag) const { return values_.count(flag) != 0; }
  bool on(const std::string& sw) const { return switches_.count(sw) != 0; }
  // Last value of a flag, or `fallback`.
  std::string get(const std::string& flag, const std::string& fallback = "") const;
  // Every value of a repeatable flag, in order.
  std::vector<std::string> all(const std::string& flag) const;
  // The value of the flag of range `id` (gather_core/input_ranges.hpp: every
  // numeric flag's range is declared there), or `fallback`; a malformed or
  // out-of-range value (a double must be finite) is a UsageError naming the
  // flag and its range.
  int get_int(range::Id id, int fallback) const;
  double get_double(range::Id id, double fallback) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::vector<std::string>> values_;
  std::map<std::string, bool> switches_;
};

}  // namespace cli
}  // namespace gather
