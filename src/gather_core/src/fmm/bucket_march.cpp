// The bucket march: FastMarching::solve() with QueueKind::kBuckets (a
// circular queue of time buckets, FIFO inside a bucket, cells re-queued when
// they improve) and kSortedBuckets (the same buckets, each expanded in exact
// time order). One instantiation per (unit speed, labels, second order, exact
// order), picked by bucket_march().
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

// Buckets of the circular queue are at most this many; slower speeds widen them.
constexpr std::size_t kMaxBuckets = std::size_t{1} << 16;

// The march with a circular bucket queue. Cells of the current bucket are
// expanded in FIFO order; a cell whose time drops after it was expanded is
// queued again, so every cell ends at the fixed point of the upwind update, as
// with an exact priority queue. Every time below the current bucket's lower
// edge is final.
template <bool kUnit, bool kLabels, bool kSecond, bool kExact>
void FastMarching::march_buckets(const SolveOptions& options) {
  const MarchGrid grid = march_grid(kLabels, options.label_look_back);
  float* const t = grid.times;
  const double width = options.bucket_width > 0.0 ? options.bucket_width : (kExact ? 0.02 : 2.0);
  double delta = width * min_cost_;  // [s]
  // The circle of buckets must span every time queued at once: an update adds
  // at most one slowest crossing (with front speed factors, scaled), and the
  // seeds of all sources spread over their own range.
  float seed_lo = kInf, seed_hi = 0.0f;
  for (const Seed& sd : seeds_) {
    seed_lo = std::min(seed_lo, t[sd.index]);
    seed_hi = std::max(seed_hi, t[sd.index]);
  }
  float max_inv_w = 1.0f;
  for (float w : inv_front_speed_) max_inv_w = std::max(max_inv_w, w);
  const double span = std::max(static_cast<double>(max_cost_) * max_inv_w,
                               seeds_.empty() ? 0.0 : static_cast<double>(seed_hi) - seed_lo) +
                      delta;
  std::size_t nb = 4;
  while (nb < static_cast<std::size_t>(std::ceil(span / delta)) + 2 && nb < kMaxBuckets) nb *= 2;
  if (span / delta + 2 > static_cast<double>(nb)) delta = span / static_cast<double>(nb - 3);
  if (buckets_.size() < nb) buckets_.resize(nb);
  const std::size_t bmask = nb - 1;
  const double inv_delta = 1.0 / delta;
  auto bucket_of = [inv_delta](float v) {
    return v < kInf ? static_cast<uint64_t>(static_cast<double>(v) * inv_delta) : ~uint64_t{0};
  };
  const float max_time = static_cast<float>(std::min(options.max_time, 3.0e38));

  std::size_t pending = 0;
  uint64_t cb = ~uint64_t{0};
  for (const Seed& sd : seeds_) {
    const uint64_t b = bucket_of(t[sd.index]);
    buckets_[b & bmask].push_back(sd.index);
    cb = std::min(cb, b);
    ++pending;
  }
  stats_.pushed = pending;
  std::size_t expanded = 0, pushed = 0;
  bool stopped = false;
  late_.clear();

  auto relax = [&](uint32_t x, float tx, float final_below, uint64_t cur) {
    relax_neighbours<kUnit, kLabels, kSecond>(grid, x, tx, final_below, [&](std::size_t n, float u, bool unreached) {
      if (unreached) note_touched(static_cast<uint32_t>(n));
      const uint64_t b = bucket_of(u);
      if (kExact && b <= cur) {
        bheap_.push_back(order_key(u, static_cast<uint32_t>(n)));
        std::push_heap(bheap_.begin(), bheap_.end(), std::greater<uint64_t>());
      } else if (b < cur) {
        late_.push_back(static_cast<uint32_t>(n));  // below the final edge (second order): expand now
      } else {
        buckets_[b & bmask].push_back(static_cast<uint32_t>(n));
        ++pending;
      }
      ++pushed;
    });
  };

  while (pending > 0) {
    std::vector<uint32_t>& bucket = buckets_[cb & bmask];
    if (bucket.empty()) {
      ++cb;
      continue;
    }
    const float lo = static_cast<float>(static_cast<double>(cb) * delta);
    if (static_cast<double>(cb) * delta > options.max_time) {
      stopped = true;
      break;
    }
    if (!targets_.empty()) {
      // Drop the final targets from the back, up to the first one that is
      // not final yet: the march goes on while one is not, and each target is
      // looked at once plus once per bucket (not all of them per bucket).
      while (!targets_.empty() && bucket_of(t[targets_.back()]) < cb) targets_.pop_back();
      if (targets_.empty()) {
        stopped = true;
        break;
      }
    }
    if constexpr (kExact) {
      // Exact order inside the bucket: its cells sorted once, merged with a
      // small heap of the cells that land in this bucket while it is expanded.
      // Keys are (time bits << 32 | cell): times are >= 0, so their bits sort
      // like the times, and duplicates of one cell end up side by side.
      sorted_.clear();
      for (uint32_t x : bucket)
        if (bucket_of(t[x]) == cb) sorted_.push_back(order_key(t[x], x));
      pending -= bucket.size();
      bucket.clear();
      std::sort(sorted_.begin(), sorted_.end());
      bheap_.clear();
      std::size_t i = 0;
      uint64_t last = ~uint64_t{0};
      while (i < sorted_.size() || !bheap_.empty()) {
        uint64_t e;
        if (bheap_.empty() || (i < sorted_.size() && sorted_[i] <= bheap_.front())) {
          e = sorted_[i++];
        } else {
          std::pop_heap(bheap_.begin(), bheap_.end(), std::greater<uint64_t>());
          e = bheap_.back();
          bheap_.pop_back();
        }
        const uint32_t x = static_cast<uint32_t>(e);
        const float tx = t[x];
        if (e == last || order_key(tx, x) != e) continue;  // a duplicate, or improved since
        last = e;
        if (tx > max_time) {
          t[x] = kInf;
          stopped = true;
          continue;
        }
        ++expanded;
        relax(x, tx, next_up(tx), cb);
      }
    } else {
      for (std::size_t i = 0; i < bucket.size(); ++i) {
        const uint32_t x = bucket[i];
        const float tx = t[x];
        if (bucket_of(tx) != cb) continue;  // stale: the cell was improved into an earlier bucket
        if (tx > max_time) {
          t[x] = kInf;  // beyond the horizon: unreached
          stopped = true;
          continue;
        }
        ++expanded;
        relax(x, tx, lo, cb);
        while (!late_.empty()) {
          const uint32_t y = late_.back();
          late_.pop_back();
          ++expanded;
          relax(y, t[y], lo, cb);
        }
      }
      pending -= bucket.size();
      bucket.clear();
    }
    ++cb;
  }
  pushed += stats_.pushed;
  if (stopped) {
    // Everything still queued is not final: unreached.
    for (std::size_t k = 0; k < nb; ++k) {
      for (uint32_t x : buckets_[k])
        if (bucket_of(t[x]) >= cb) t[x] = kInf;
      buckets_[k].clear();
    }
    stats_.stopped_early = true;
  }
  stats_.expanded = expanded;
  stats_.pushed = pushed;
}

// Every instantiation, indexed by the flags as bits: unit 8, labels 4, second 2, exact 1.
struct FastMarching::BucketMarches {
  template <std::size_t... I>
  static constexpr std::array<March, sizeof...(I)> table(std::index_sequence<I...>) {
    return {{&FastMarching::march_buckets<(I & 8u) != 0, (I & 4u) != 0, (I & 2u) != 0, (I & 1u) != 0>...}};
  }
};

FastMarching::March FastMarching::bucket_march(bool unit, bool labels, bool second, bool exact) {
  static constexpr std::array<March, 16> kTable = BucketMarches::table(std::make_index_sequence<16>());
  return kTable[(unit ? 8u : 0u) | (labels ? 4u : 0u) | (second ? 2u : 0u) | (exact ? 1u : 0u)];
}

}  // namespace fmm
}  // namespace gather
