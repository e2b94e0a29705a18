#pragma once
// Numeric constants and helpers shared by the planner and the simulator (one
// definition: the sanitized build of make test compiles several sources as
// one unit).
#include <cstdint>
#include <cstring>
#include <limits>

namespace gather {

// "Never" or "not reached": a time or distance above every finite one.
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// A sort key of (time, index), times >= 0: the bits of such a float order
// like the float, so keys order by time, then by index (the FMM's queues,
// the partitions' seeding march, a segment's cells by distance).
inline uint64_t order_key(float time, uint32_t index) {
  uint32_t bits;
  std::memcpy(&bits, &time, sizeof bits);
  return (static_cast<uint64_t>(bits) << 32) | index;
}

// The time of an order_key.
inline float order_key_time(uint64_t key) {
  const auto bits = static_cast<uint32_t>(key >> 32);
  float time;
  std::memcpy(&time, &bits, sizeof time);
  return time;
}

}  // namespace gather
