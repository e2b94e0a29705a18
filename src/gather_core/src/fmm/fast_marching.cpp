#include "gather_core/fmm/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace fmm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Buckets of the circular queue are at most this many; slower speeds widen them.
constexpr std::size_t kMaxBuckets = std::size_t{1} << 16;

std::string cell_text(Cell c) { return "(" + std::to_string(c.row) + ", " + std::to_string(c.col) + ")"; }

// First-order upwind update of the cell at `n` from its four neighbours' current
// times; `c` is the time to cross the cell [s]. Times of obstacles and cells not
// reached yet are +inf, so they never take part.
inline float update_first(const float* t, std::size_t n, std::size_t stride, float c) {
  const float a = std::min(t[n - 1], t[n + 1]);
  const float b = std::min(t[n - stride], t[n + stride]);
  const float lo = std::min(a, b);
  const float hi = std::max(a, b);
  const float d = hi - lo;
  if (!(d < c)) return lo + c;  // one-sided (also when hi is +inf)
  return 0.5f * (lo + hi + std::sqrt(2.0f * c * c - d * d));
}

// One axis of the second-order update: the upwind neighbour t1 and, when the
// cell beyond it is final and further upwind, the second-order term.
struct Axis {
  float t1;     // upwind neighbour time, +inf when none
  float beta;   // the axis' equation is (a (T - beta))^2
  float a;      // 1 (first order) or 3/2 (second order)
};

inline Axis upwind_axis(const float* t, std::size_t n, std::size_t off, float final_below) {
  const float l = t[n - off];
  const float r = t[n + off];
  const bool left = l <= r;
  const float t1 = left ? l : r;
  const float t2 = left ? t[n - 2 * off] : t[n + 2 * off];
  if (t2 <= t1 && t2 < final_below) return Axis{t1, (4.0f * t1 - t2) * (1.0f / 3.0f), 1.5f};
  return Axis{t1, t1, 1.0f};
}

inline float update_second(const float* t, std::size_t n, std::size_t stride, float c, float final_below) {
  const Axis x = upwind_axis(t, n, 1, final_below);
  const Axis y = upwind_axis(t, n, stride, final_below);
  const float sx = x.beta + c * (x.a > 1.0f ? 2.0f / 3.0f : 1.0f);  // one-sided solutions: beta + c / a
  const float sy = y.beta + c * (y.a > 1.0f ? 2.0f / 3.0f : 1.0f);
  const float single = std::min(sx, sy);
  // The two-axis solution lies between max(t1) and `single`: none when the
  // one-sided one is already below the later neighbour (also when one is +inf).
  if (!(single > std::max(x.t1, y.t1))) return single;
  // Two axes: a_x^2 (T-bx)^2 + a_y^2 (T-by)^2 = c^2, shifted by m so that float
  // keeps its precision far from the sources.
  const float m = std::min(x.beta, y.beta);
  const float bx = x.beta - m, by = y.beta - m;
  const float ax2 = x.a * x.a, ay2 = y.a * y.a;
  const float A = ax2 + ay2;
  const float B = ax2 * bx + ay2 * by;
  const float C = ax2 * bx * bx + ay2 * by * by - c * c;
  const float disc = B * B - A * C;
  if (disc < 0.0f) return single;
  const float two = m + (B + std::sqrt(disc)) / A;
  if (two < std::max(x.t1, y.t1)) return single;  // not upwind of both neighbours
  return std::min(two, single);
}

// Sort key of a queued cell: the bits of a time >= 0 order like the time.
inline uint64_t order_key(float time, uint32_t cell) {
  uint32_t bits;
  std::memcpy(&bits, &time, sizeof bits);
  return (static_cast<uint64_t>(bits) << 32) | cell;
}

// The next float above a finite time >= 0 (std::nextafter without the call).
inline float next_up(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  ++bits;
  std::memcpy(&v, &bits, sizeof bits);
  return v;
}

// The label of a cell is that of its earliest neighbour: the front that set
// the larger part of its time (the cell whose expansion triggered the update
// may be a later front that only shaved it).
inline std::size_t upwind_neighbour(const float* t, std::size_t n, std::size_t stride) {
  std::size_t best = n - 1;
  if (t[n + 1] < t[best]) best = n + 1;
  if (t[n - stride] < t[best]) best = n - stride;
  if (t[n + stride] < t[best]) best = n + stride;
  return best;
}

// Label of an expanded cell from the cell `steps` cells back along its
// characteristic (against the upwind gradient), when the straight way there is
// free and earlier. Copying the label of the earliest neighbour alone snaps the
// characteristic to a grid axis at every cell, and near a collision of two
// fronts that drift adds up; looking several cells back bounds it.
inline void look_back_label(const float* t, int32_t* lab, const uint8_t* mask, std::size_t stride, uint32_t x,
                            int steps) {
  const float tx = t[x];
  const float l = t[x - 1], r = t[x + 1], d = t[x - stride], u = t[x + stride];
  // Inside one front's region the neighbour's label is right: look back only
  // where a reached neighbour carries another label (where drift would start).
  const int32_t lx = lab[x];
  if (!((l < kInf && lab[x - 1] != lx) || (r < kInf && lab[x + 1] != lx) || (d < kInf && lab[x - stride] != lx) ||
        (u < kInf && lab[x + stride] != lx)))
    return;
  float gx = 0.0f, gy = 0.0f;
  if (std::min(l, r) < tx) gx = l < r ? tx - l : r - tx;
  if (std::min(d, u) < tx) gy = d < u ? tx - d : u - tx;
  const float g = std::sqrt(gx * gx + gy * gy);
  if (!(g > 0.0f)) return;
  const float dx = -gx / g, dy = -gy / g;
  const float px = static_cast<float>(x % stride), py = static_cast<float>(x / stride);
  std::size_t m = x;
  for (int k = 1; k <= steps; ++k) {
    // Padded coordinates stay >= 0 (the walk stops at the border), so +0.5 and truncation round.
    const auto cx = static_cast<std::size_t>(px + k * dx + 0.5f), cy = static_cast<std::size_t>(py + k * dy + 0.5f);
    m = cy * stride + cx;
    if (!mask[m] || !(t[m] < tx)) return;  // blocked or not upwind: keep the neighbour's label
  }
  lab[x] = lab[m];
}

// A march's arrays as raw pointers, taken once per march.
struct MarchGrid {
  float* t;
  int32_t* lab;            // nullptr without labels
  const uint8_t* mask;
  const float* cost;       // nullptr on a unit-speed map
  float ucost;
  std::size_t s;           // stride
  bool weighted;           // per-front speed factors
  const float* inv_w;
  int look_back;
};

// Expands cell x (time tx): every 4-neighbour whose upwind update lowers its
// time gets the new time u (and the label of its upwind front) and is handed
// to `lowered(n, u, was_unreached)` to be queued. The one relax loop of the
// bucket and the heap marches.
template <bool kUnit, bool kLabels, bool kSecond, class Lowered>
inline void relax_neighbours(const MarchGrid& g, uint32_t x, float tx, float final_below, Lowered&& lowered) {
  float* const t = g.t;
  const std::size_t s = g.s;
  if (kLabels && g.look_back > 0) look_back_label(t, g.lab, g.mask, s, x, g.look_back);
  const std::size_t offs[4] = {1, s, static_cast<std::size_t>(-1), static_cast<std::size_t>(0) - s};
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = x + offs[k];
    if (!g.mask[n]) continue;
    const float tn = t[n];
    if (!(tn > tx)) continue;
    float c = kUnit ? g.ucost : g.cost[n];
    std::size_t up = 0;
    if (kLabels && g.weighted) {  // the front's own speed factor, from the front that leads here
      up = upwind_neighbour(t, n, s);
      c *= g.inv_w[g.lab[up]];
    }
    const float u = kSecond ? update_second(t, n, s, c, final_below) : update_first(t, n, s, c);
    if (u < tn) {
      t[n] = u;
      if (kLabels) g.lab[n] = g.lab[g.weighted ? up : upwind_neighbour(t, n, s)];
      lowered(n, u, !(tn < kInf));
    }
  }
}

}  // namespace

FastMarching::FastMarching(const OccupancyGrid& grid)
    : width_(grid.width()),
      height_(grid.height()),
      stride_(static_cast<std::size_t>(grid.width()) + 2 * kPad),
      resolution_(grid.resolution()),
      origin_(grid.origin()) {
  const std::size_t rows = static_cast<std::size_t>(height_) + 2 * kPad;
  if (rows * stride_ >= std::numeric_limits<uint32_t>::max())
    throw Error("fmm", "grid of " + std::to_string(width_) + " x " + std::to_string(height_) + " cells is too large");
  mask_.assign(rows * stride_, 0);
  const auto& free = grid.free_mask();
  for (int r = 0; r < height_; ++r)
    for (int c = 0; c < width_; ++c)
      mask_[padded(Cell{r, c})] = free[static_cast<std::size_t>(r) * width_ + c] != 0 ? 1 : 0;
  set_unit_speed();
}

void FastMarching::reserve_work(std::size_t targets, std::size_t front) {
  targets_.reserve(targets);
  seeds_.reserve(16);
  sources_.reserve(4);
  if (buckets_.size() < 16) buckets_.resize(16);
  for (auto& b : buckets_) b.reserve(front);
  late_.reserve(front);
  if (times_.size() != mask_.size()) reset_times();  // sizes the times and the reset list
}

void FastMarching::set_unit_speed() {
  cost_.clear();
  cost_.shrink_to_fit();
  unit_cost_ = static_cast<float>(resolution_);
  min_cost_ = max_cost_ = unit_cost_;
}

void FastMarching::set_speed(const std::vector<double>& speed) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (speed.size() != n)
    throw Error("speed map", "has " + std::to_string(speed.size()) + " cells, the grid " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    const double f = speed[i];
    if (!(f >= 0.0) || !std::isfinite(f))
      throw Error("speed map", "speed " + std::to_string(f) + " m/s at cell " +
                                   cell_text(Cell{static_cast<int>(i / width_), static_cast<int>(i % width_)}) +
                                   " (must be finite and >= 0)");
  }
  cost_.assign(mask_.size(), kInf);
  double fmax = 0.0, fmin = kUnreached;
  for (int r = 0; r < height_; ++r) {
    for (int c = 0; c < width_; ++c) {
      const double f = speed[static_cast<std::size_t>(r) * width_ + c];
      const std::size_t p = padded(Cell{r, c});
      if (f > 0.0 && mask_[p]) {
        cost_[p] = static_cast<float>(resolution_ / f);
        fmax = std::max(fmax, f);
        fmin = std::min(fmin, f);
      }
    }
  }
  // Zero speed blocks the cell through its +inf cost: the update there is +inf.
  if (fmax > 0.0) {
    min_cost_ = static_cast<float>(resolution_ / fmax);
    max_cost_ = static_cast<float>(resolution_ / fmin);
  }
}

double FastMarching::speed(Cell c) const {
  if (!traversable(c)) return 0.0;
  return cost_.empty() ? 1.0 : resolution_ / cost_[padded(c)];
}

double FastMarching::slowness(Cell c) const {
  if (!traversable(c)) return kUnreached;
  return cost_at(padded(c)) / resolution_;
}

void FastMarching::reset_times() {
  if (times_.size() != mask_.size()) {
    times_.assign(mask_.size(), kInf);
    touched_limit_ = mask_.size() / 8;
    touched_.reserve(touched_limit_);
  } else if (touched_overflow_) {
    std::fill(times_.begin(), times_.end(), kInf);
  } else {
    for (uint32_t p : touched_) times_[p] = kInf;
  }
  touched_.clear();
  touched_overflow_ = false;
}

void FastMarching::seed(const std::vector<Source>& sources, bool labels) {
  seeds_.clear();
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const Source& s = sources[i];
    const std::string where = "source " + std::to_string(i);
    double qx, qy;  // position in cell units, cell (r, c) spans [c, c+1) x [r, r+1)
    Cell base;
    if (s.is_point) {
      if (!std::isfinite(s.point.x) || !std::isfinite(s.point.y)) throw Error(where, "point is not finite");
      qx = (s.point.x - origin_.x) / resolution_;
      qy = (s.point.y - origin_.y) / resolution_;
      base = Cell{static_cast<int>(std::floor(qy)), static_cast<int>(std::floor(qx))};
      if (!contains(base) || !(std::abs(qx) < 1e9 && std::abs(qy) < 1e9))
        throw Error(where, "point [" + std::to_string(s.point.x) + ", " + std::to_string(s.point.y) +
                               "] m is off the map");
    } else {
      base = s.cell;
      if (!contains(base))
        throw Error(where, "cell " + cell_text(base) + " is off the map (" + std::to_string(height_) + " rows x " +
                               std::to_string(width_) + " cols)");
      qx = base.col + 0.5;
      qy = base.row + 0.5;
    }
    if (!traversable(base))
      throw Error(where, "cell " + cell_text(base) + " is an obstacle" + (cost_.empty() ? "" : " or has zero speed"));
    const float base_cost =
        cost_at(padded(base)) * (inv_front_speed_.empty() ? 1.0f : inv_front_speed_[i]);
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell n{base.row + dr, base.col + dc};
        if (!traversable(n)) continue;
        // A diagonal cell is in straight sight only when both cells between are free.
        if (dr != 0 && dc != 0 && (!traversable(Cell{base.row + dr, base.col}) || !traversable(Cell{base.row, base.col + dc})))
          continue;
        const std::size_t p = padded(n);
        const double d = std::hypot(n.col + 0.5 - qx, n.row + 0.5 - qy);  // [cells]
        const double scale = inv_front_speed_.empty() ? 1.0 : inv_front_speed_[i];
        const double cost = (dr == 0 && dc == 0) ? base_cost : 0.5 * (base_cost + cost_at(p) * scale);
        const float v = static_cast<float>(d * cost);
        seeds_.push_back(Seed{static_cast<uint32_t>(p), static_cast<int32_t>(i), v});
        if (v < times_[p]) {
          if (!(times_[p] < kInf)) note_touched(static_cast<uint32_t>(p));
          times_[p] = v;
          if (labels) labels_[p] = static_cast<int32_t>(i);
        }
      }
    }
  }
  // Keep the seeds that won their cell (several sources may seed one cell).
  seeds_.erase(std::remove_if(seeds_.begin(), seeds_.end(),
                              [&](const Seed& s) {
                                return times_[s.index] != s.time || (labels && labels_[s.index] != s.source);
                              }),
               seeds_.end());
}

const SolveStats& FastMarching::solve(const std::vector<Source>& sources, const SolveOptions& options) {
  if (mask_.empty()) throw Error("fmm", "workspace is not bound to a grid");
  if (sources.empty()) throw Error("fmm", "no sources given");
  if (options.order != Order::kFirst && options.order != Order::kSecond)
    throw Error("fmm", "order must be 1 or 2");
  if (!(options.bucket_width >= 0.0) || !std::isfinite(options.bucket_width))
    throw Error("fmm", "bucket_width must be >= 0");
  if (std::isnan(options.max_time) || options.max_time < 0.0) throw Error("fmm", "max_time must be >= 0");
  if (options.label_look_back < 0 || options.label_look_back > 64)
    throw Error("fmm", "label_look_back must be in 0..64 cells");
  targets_.clear();
  for (std::size_t i = 0; i < options.targets.size(); ++i) {
    const Cell c = options.targets[i];
    if (!contains(c))
      throw Error("target " + std::to_string(i), "cell " + cell_text(c) + " is off the map");
    if (traversable(c)) targets_.push_back(static_cast<uint32_t>(padded(c)));  // an obstacle is never reached
  }
  inv_front_speed_.clear();
  if (!options.front_speed.empty()) {
    if (options.front_speed.size() != sources.size())
      throw Error("fmm", "front_speed has " + std::to_string(options.front_speed.size()) + " factors for " +
                             std::to_string(sources.size()) + " sources");
    if (!options.labels) throw Error("fmm", "front_speed needs labels");
    for (std::size_t i = 0; i < options.front_speed.size(); ++i) {
      const double w = options.front_speed[i];
      if (!(w > 0.0) || !std::isfinite(w))
        throw Error("source " + std::to_string(i), "front speed factor " + std::to_string(w) + " (must be > 0)");
      inv_front_speed_.push_back(static_cast<float>(1.0 / w));
    }
  }
  if (options.labels && labels_.size() != mask_.size()) labels_.assign(mask_.size(), -1);
  labels_on_ = options.labels;
  sources_ = sources;

  reset_times();
  try {
    seed(sources, options.labels);
  } catch (...) {
    reset_times();  // no half-seeded field is left behind: everything reads unreached
    seeds_.clear();
    throw;
  }
  stats_ = SolveStats{};

  const bool unit = cost_.empty();
  const bool second = options.order == Order::kSecond;
  const bool lab = options.labels;
  QueueKind queue = options.queue;
  if (queue == QueueKind::kAuto) queue = second ? QueueKind::kSortedBuckets : QueueKind::kBuckets;
#define GATHER_FMM_DISPATCH(U, L, S)                         \
  if (unit == U && lab == L && second == S) {                \
    if (queue == QueueKind::kHeap) march_heap<U, L, S>(options);              \
    else if (queue == QueueKind::kSortedBuckets) march_buckets<U, L, S, true>(options); \
    else march_buckets<U, L, S, false>(options);                           \
  }
  GATHER_FMM_DISPATCH(true, true, true)
  GATHER_FMM_DISPATCH(true, true, false)
  GATHER_FMM_DISPATCH(true, false, true)
  GATHER_FMM_DISPATCH(true, false, false)
  GATHER_FMM_DISPATCH(false, true, true)
  GATHER_FMM_DISPATCH(false, true, false)
  GATHER_FMM_DISPATCH(false, false, true)
  GATHER_FMM_DISPATCH(false, false, false)
#undef GATHER_FMM_DISPATCH

  return stats_;
}

// The march with a circular bucket queue. Cells of the current bucket are
// expanded in FIFO order; a cell whose time drops after it was expanded is
// queued again, so every cell ends at the fixed point of the upwind update, as
// with an exact priority queue. Every time below the current bucket's lower
// edge is final.
template <bool kUnit, bool kLabels, bool kSecond, bool kExact>
void FastMarching::march_buckets(const SolveOptions& options) {
  float* const t = times_.data();
  int32_t* const lab = kLabels ? labels_.data() : nullptr;
  const uint8_t* const mask = mask_.data();
  const float* const cost = kUnit ? nullptr : cost_.data();
  const float ucost = unit_cost_;
  const std::size_t s = stride_;
  const bool weighted = !inv_front_speed_.empty();
  const float* const inv_w = inv_front_speed_.data();
  const int look_back = options.label_look_back;

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
                               seeds_.empty() ? 0.0 : static_cast<double>(seed_hi) - seed_lo) + delta;
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

  const MarchGrid grid{t, lab, mask, cost, ucost, s, weighted, inv_w, look_back};
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

// Classical FMM: a binary min-heap with lazy deletion (an improved cell is
// pushed again; the outdated entry is skipped when popped).
template <bool kUnit, bool kLabels, bool kSecond>
void FastMarching::march_heap(const SolveOptions& options) {
  float* const t = times_.data();
  int32_t* const lab = kLabels ? labels_.data() : nullptr;
  const uint8_t* const mask = mask_.data();
  const float* const cost = kUnit ? nullptr : cost_.data();
  const float ucost = unit_cost_;
  const std::size_t s = stride_;
  const bool weighted = !inv_front_speed_.empty();
  const float* const inv_w = inv_front_speed_.data();
  const int look_back = options.label_look_back;
  const MarchGrid grid{t, lab, mask, cost, ucost, s, weighted, inv_w, look_back};
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

std::size_t FastMarching::count_reached() const {
  return static_cast<std::size_t>(std::count_if(times_.begin(), times_.end(), [](float v) { return v < kInf; }));
}

double FastMarching::time(Cell c) const {
  if (!contains(c) || times_.empty()) return kUnreached;
  const float v = times_[padded(c)];
  return v < kInf ? static_cast<double>(v) : kUnreached;
}

int FastMarching::label(Cell c) const {
  if (!labels_on_ || !contains(c) || times_.empty()) return -1;
  const std::size_t p = padded(c);
  return times_[p] < kInf ? labels_[p] : -1;
}

double FastMarching::time_at(Point2 pt) const {
  if (times_.empty()) return kUnreached;
  const double qx = (pt.x - origin_.x) / resolution_;
  const double qy = (pt.y - origin_.y) / resolution_;
  if (!(std::abs(qx) < 1e9 && std::abs(qy) < 1e9)) return kUnreached;
  const Cell base{static_cast<int>(std::floor(qy)), static_cast<int>(std::floor(qx))};
  if (!traversable(base)) return kUnreached;
  const double base_cost = cost_at(padded(base));
  double best = kUnreached;
  const int dr[5] = {0, 1, -1, 0, 0};
  const int dc[5] = {0, 0, 0, 1, -1};
  for (int k = 0; k < 5; ++k) {
    const Cell n{base.row + dr[k], base.col + dc[k]};
    if (!traversable(n)) continue;
    const std::size_t p = padded(n);
    if (!(times_[p] < kInf)) continue;
    const double d = std::hypot(n.col + 0.5 - qx, n.row + 0.5 - qy);
    const double cost = k == 0 ? base_cost : 0.5 * (base_cost + cost_at(p));
    best = std::min(best, static_cast<double>(times_[p]) + d * cost);
  }
  return best;
}

void FastMarching::copy_times(std::vector<double>& out) const {
  out.resize(static_cast<std::size_t>(width_) * height_);
  for (int r = 0; r < height_; ++r) {
    const float* row = times_.empty() ? nullptr : &times_[padded(Cell{r, 0})];
    double* o = &out[static_cast<std::size_t>(r) * width_];
    for (int c = 0; c < width_; ++c) o[c] = row && row[c] < kInf ? static_cast<double>(row[c]) : kUnreached;
  }
}

void FastMarching::copy_labels(std::vector<int32_t>& out) const {
  out.assign(static_cast<std::size_t>(width_) * height_, -1);
  if (!labels_on_ || times_.empty()) return;
  for (int r = 0; r < height_; ++r) {
    const std::size_t p = padded(Cell{r, 0});
    int32_t* o = &out[static_cast<std::size_t>(r) * width_];
    for (int c = 0; c < width_; ++c) o[c] = times_[p + c] < kInf ? labels_[p + c] : -1;
  }
}

std::size_t FastMarching::working_bytes() const {
  std::size_t b = mask_.capacity() + cost_.capacity() * sizeof(float) + times_.capacity() * sizeof(float) +
                  labels_.capacity() * sizeof(int32_t) + touched_.capacity() * sizeof(uint32_t) +
                  heap_.capacity() * sizeof(HeapEntry) + (sorted_.capacity() + bheap_.capacity()) * sizeof(uint64_t) + inv_front_speed_.capacity() * sizeof(float) + late_.capacity() * sizeof(uint32_t) + targets_.capacity() * sizeof(uint32_t) +
                  seeds_.capacity() * sizeof(Seed) + sources_.capacity() * sizeof(Source);
  for (const auto& v : buckets_) b += v.capacity() * sizeof(uint32_t) + sizeof(v);
  return b;
}

}  // namespace fmm
}  // namespace gather
