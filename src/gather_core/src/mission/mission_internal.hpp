#pragma once
// What the simulator and the worker policy share inside gather_core (not
// installed): the time tolerance and the internal-error exit.
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/numeric.hpp"

namespace gather {
namespace mission {

inline constexpr double kEps = 1e-9;  // [s] time tolerance

// A broken invariant of the mission code (not bad input).
[[noreturn]] inline void bug(const std::string& what) { throw RuntimeError("mission (internal error)", what); }

}  // namespace mission
}  // namespace gather
