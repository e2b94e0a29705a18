#include "gather_agent/transport/range_gate.hpp"

#include <algorithm>

namespace gather {
namespace agent {
namespace {

uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace

RangeGate::RangeGate(const TeamSetup& team, double loss, uint64_t loss_seed)
    : team_(team), loss_(loss), seed_(loss_seed) {}

RangeGate::Verdict RangeGate::admit(const Header& h, int16_t receiver, Point2 at) const {
  if (!team_.linked(h.pos, at)) return Verdict::kOutOfRange;
  if (loss_ > 0.0) {
    uint64_t x = splitmix64(seed_);
    x = splitmix64(x ^ static_cast<uint64_t>(static_cast<uint16_t>(h.sender)));
    x = splitmix64(x ^ h.seq);
    x = splitmix64(x ^ static_cast<uint64_t>(static_cast<uint16_t>(receiver)));
    if (static_cast<double>(x >> 11) * 0x1.0p-53 < loss_) return Verdict::kLost;
  }
  return Verdict::kPass;
}

void gather_inbox(const std::vector<Message>& sent, int16_t receiver, Point2 at, const RangeGate& gate,
                  LinkCounters& counters, std::vector<const Message*>& inbox) {
  inbox.clear();
  for (const Message& m : sent) {
    // Addressed to it, or a broadcast from one of its links (FleetLinks):
    // what it can authenticate, in one process as over LCM.
    if (!gate.team().links.hears(receiver, m.h.sender, m.h.dest)) continue;
    switch (gate.admit(m.h, receiver, at)) {
      case RangeGate::Verdict::kOutOfRange: ++counters.gated; continue;
      case RangeGate::Verdict::kLost: ++counters.lost; continue;
      case RangeGate::Verdict::kPass: break;
    }
    if (inbox.size() >= inbox.capacity()) {
      ++counters.overflow;
      continue;
    }
    inbox.push_back(&m);
    ++counters.received;
  }
  std::sort(inbox.begin(), inbox.end(), [](const Message* a, const Message* b) {
    return a->h.sender != b->h.sender ? a->h.sender < b->h.sender : a->h.seq < b->h.seq;
  });
}

}  // namespace agent
}  // namespace gather
