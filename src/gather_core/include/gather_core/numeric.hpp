#pragma once
// Numeric constants shared by the planner and the simulator (one definition:
// the sanitized build of make test compiles several sources as one unit).
#include <limits>

namespace gather {

// "Never" or "not reached": a time or distance above every finite one.
inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace gather
