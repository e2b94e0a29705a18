#include "gather_core/input_ranges.hpp"

#include <cmath>
#include <sstream>

#include "gather_core/error.hpp"

namespace gather {

bool InputRange::accepts(double v) const {
  if (!std::isfinite(v)) return false;
  if ((flags & kRangeZero) != 0 && v == 0.0) return true;
  if (integer() && v != std::floor(v)) return false;
  const bool above_lo = (flags & kRangeOpenLo) != 0 ? v > lo : v >= lo;
  const bool below_hi = (flags & kRangeOpenHi) != 0 ? v < hi : v <= hi;
  return above_lo && below_hi;
}

std::string InputRange::text() const {
  std::ostringstream s;
  s.precision(12);
  if ((flags & kRangeZero) != 0) s << "0 or ";
  s << ((flags & kRangeOpenLo) != 0 ? "(" : "[") << lo << ", " << hi << ((flags & kRangeOpenHi) != 0 ? ")" : "]")
    << unit;
  if (integer()) s << " (an integer)";
  return s.str();
}

const std::vector<InputRange>& input_ranges() {
  static const std::vector<InputRange> kAll = {
#define GATHER_RANGE_ENTRY(name, input, key, lo, hi, unit, flags, coupled) \
  InputRange{input, key, lo, hi, unit, static_cast<std::uint8_t>(flags), coupled},
      GATHER_INPUT_RANGES(GATHER_RANGE_ENTRY)
#undef GATHER_RANGE_ENTRY
  };
  return kAll;
}

const InputRange& input_range(range::Id id) { return input_ranges().at(id); }

void check_range(range::Id id, double v, const std::string& where) {
  const InputRange& r = input_range(id);
  if (r.accepts(v)) return;
  std::ostringstream s;
  s.precision(12);
  s << r.key << " = " << v << " must be in " << r.text();
  throw Error(where, s.str());
}

}  // namespace gather
