// The heap march: FastMarching::solve() with QueueKind::kHeap, the classical
// FMM on a binary min-heap. One instantiation per (unit speed, labels, second
// order), picked by heap_march().
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <utility>

#include "gather_core/fmm/fast_marching.hpp"
#include "stencil.hpp"

namespace gather {
namespace fmm {

using namespace detail;  // stencil.hpp

// Classical FMM: a binary min-heap with lazy deletion (an improved cell is
// pushed again; the outdated entry is skipped when popped).
template <bool kUnit, bool kLabels, bool kSecond>
void FastMarching::march_heap(const SolveOptions& options) {
  const MarchGrid grid = march_grid(kLabels, options.label_look_back);
  float* const t = grid.times;
  auto later = [](const HeapEntry& a, const HeapEntry& b) { return a.key > b.key; };

  heap_.clear();
  for (const Seed& sd : seeds_) heap_.push_back(HeapEntry{t[sd.index], sd.index});
  std::make_heap(heap_.begin(), heap_.end(), later);
  std::size_t expanded = 0, pushed = heap_.size();
  std::size_t targets_left = targets_.size();
  std::sort(targets_.begin(), targets_.end());  // looked up per expanded cell: a binary search, not a scan
  bool stopped = false;
  const float max_time = static_cast<float>(std::min(options.max_time, 3.0e38));

  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const HeapEntry e = heap_.back();
    heap_.pop_back();
    const uint32_t x = e.index;
    const float tx = t[x];
    if (e.key != tx) continue;
    if (tx > max_time) {
      heap_.push_back(e);  // let the trim below clear it
      stopped = true;
      break;
    }
    ++expanded;
    if (targets_left > 0 && std::binary_search(targets_.begin(), targets_.end(), x)) {
      if (--targets_left == 0) stopped = true;  // expand it anyway: harmless, keeps neighbours consistent
    }
    relax_neighbours<kUnit, kLabels, kSecond>(grid, x, tx, next_up(tx), [&](std::size_t n, float u, bool unreached) {
      if (unreached) note_touched(static_cast<uint32_t>(n));
      heap_.push_back(HeapEntry{u, static_cast<uint32_t>(n)});
      std::push_heap(heap_.begin(), heap_.end(), later);
      ++pushed;
    });
    if (stopped) break;
  }
  if (stopped) {
    for (const HeapEntry& e : heap_)
      if (t[e.index] == e.key) t[e.index] = kInf;
    heap_.clear();
    stats_.stopped_early = true;
  }
  stats_.expanded = expanded;
  stats_.pushed = pushed;
}

// Every instantiation, indexed by the flags as bits: unit 4, labels 2, second 1.
struct FastMarching::HeapMarches {
  template <std::size_t... I>
  static constexpr std::array<March, sizeof...(I)> table(std::index_sequence<I...>) {
    return {{&FastMarching::march_heap<(I & 4u) != 0, (I & 2u) != 0, (I & 1u) != 0>...}};
  }
};

FastMarching::March FastMarching::heap_march(bool unit, bool labels, bool second) {
  static constexpr std::array<March, 8> kTable = HeapMarches::table(std::make_index_sequence<8>());
  return kTable[(unit ? 4u : 0u) | (labels ? 2u : 0u) | (second ? 1u : 0u)];
}

}  // namespace fmm
}  // namespace gather
