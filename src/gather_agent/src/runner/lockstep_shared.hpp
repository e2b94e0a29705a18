#pragma once
// What both sides of the lockstep (lockstep_agent.cpp, lockstep_master.cpp)
// share: the radio messages held for the ticks to come, taken tick by tick
// in (sender, seq) order, and the clocks. Internal to gather_agent.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_agent/runner/lockstep.hpp"

namespace gather {
namespace agent {
namespace lockstep {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kHeld = 8192;  // radio messages held for the ticks to come
constexpr std::size_t kOutbox = 64;  // messages a role sends in one tick

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline bool signalled(ShutdownSignal* s) { return s && s->wait_until(Clock::now()); }

// Moves the messages of `tick` - 1 from `held` into `current` (and drops,
// counting them, any older ones that came too late).
inline void take_tick(std::vector<Message>& held, std::vector<Message>& current, int64_t tick, int64_t& late) {
  current.clear();
  std::size_t keep = 0;
  for (std::size_t i = 0; i < held.size(); ++i) {
    if (held[i].h.tick == tick - 1)
      current.push_back(held[i]);
    else if (held[i].h.tick < tick - 1)
      ++late;
    else
      held[keep++] = held[i];
  }
  held.resize(keep);
  // In (sender, seq) order, as the in-process runner has them: an inbox that
  // overflows keeps the same messages whatever the arrival order.
  std::sort(current.begin(), current.end(), [](const Message& a, const Message& b) {
    return a.h.sender != b.h.sender ? a.h.sender < b.h.sender : a.h.seq < b.h.seq;
  });
}

inline std::size_t count_tick(const std::vector<Message>& held, int64_t tick) {
  std::size_t n = 0;
  for (const Message& m : held) n += m.h.tick == tick - 1;
  return n;
}

inline void absorb(LcmFleet& fleet, std::vector<Message>& held, LinkCounters& link) {
  for (const Message& m : fleet.radio()) {
    if (held.size() >= held.capacity()) {
      ++link.overflow;
      continue;
    }
    held.push_back(m);
  }
  fleet.radio().clear();
}

}  // namespace lockstep
}  // namespace agent
}  // namespace gather
