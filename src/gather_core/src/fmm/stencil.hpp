#pragma once
// The FMM's local update (the stencil), shared by the bucket march
// (bucket_march.cpp) and the heap march (heap_march.cpp): first- and
// second-order upwind updates of one cell, the label rules, and the relax
// loop over a cell's four neighbours. Header-only and inline: it is the inner
// loop of every march. Internal to gather_core (not installed): include it
// only from src/fmm/*.cpp.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/numeric.hpp"  // order_key: the sort key of a queued cell

namespace gather {
namespace fmm {
namespace detail {

// A march's arrays as raw pointers, taken once per march (padded layout).
struct MarchGrid {
  float* times;                  // [s], +inf = not reached yet
  int32_t* labels;               // source per cell; nullptr without labels
  const uint8_t* free;           // 1 = traversable
  const float* cost;             // [s per cell]; nullptr on a unit-speed map
  float unit_cost;               // [s per cell] on a unit-speed map
  std::size_t stride;            // cells per padded row
  bool weighted;                 // per-front speed factors
  const float* inv_front_speed;  // 1 / factor, per source
  int look_back;                 // [cells] label look-back, 0 = off
};

// Internal linkage, as when these lived in one file: each march's file gets
// its own copies, which GCC inlines into the hot loop as it did then (as
// external inline functions they were about 10% slower, farm-bench).
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

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
  float t1;    // upwind neighbour time, +inf when none
  float beta;  // the axis' equation is (a (T - beta))^2
  float a;     // 1 (first order) or 3/2 (second order)
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
  const std::size_t col = x % stride, row = x / stride;
  const float px = static_cast<float>(col), py = static_cast<float>(row);
  std::size_t m = x;
  for (int k = 1; k <= steps; ++k) {
    // Padded coordinates stay >= 0 (the walk stops at the border), so +0.5 and truncation round.
    // NOLINTNEXTLINE(bugprone-incorrect-roundings): that is the rounding meant, without a call in the hot loop.
    const auto cx = static_cast<std::size_t>(px + k * dx + 0.5f), cy = static_cast<std::size_t>(py + k * dy + 0.5f);
    m = cy * stride + cx;
    if (!mask[m] || !(t[m] < tx)) return;  // blocked or not upwind: keep the neighbour's label
  }
  lab[x] = lab[m];
}

// Expands cell x (time tx): every 4-neighbour whose upwind update lowers its
// time gets the new time u (and the label of its upwind front) and is handed
// to `lowered(n, u, was_unreached)` to be queued. The one relax loop of the
// bucket and the heap marches.
template <bool kUnit, bool kLabels, bool kSecond, class Lowered>
inline void relax_neighbours(const MarchGrid& g, uint32_t x, float tx, float final_below, Lowered&& lowered) {
  float* const t = g.times;
  const std::size_t s = g.stride;
  if (kLabels && g.look_back > 0) look_back_label(t, g.labels, g.free, s, x, g.look_back);
  const std::size_t offs[4] = {1, s, static_cast<std::size_t>(-1), static_cast<std::size_t>(0) - s};
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = x + offs[k];
    if (!g.free[n]) continue;
    const float tn = t[n];
    if (!(tn > tx)) continue;
    float c = kUnit ? g.unit_cost : g.cost[n];
    std::size_t up = 0;
    if (kLabels && g.weighted) {  // the front's own speed factor, from the front that leads here
      up = upwind_neighbour(t, n, s);
      c *= g.inv_front_speed[g.labels[up]];
    }
    const float u = kSecond ? update_second(t, n, s, c, final_below) : update_first(t, n, s, c);
    if (u < tn) {
      t[n] = u;
      if (kLabels) g.labels[n] = g.labels[g.weighted ? up : upwind_neighbour(t, n, s)];
      lowered(n, u, !(tn < kInf));
    }
  }
}

}  // namespace
}  // namespace detail

// Inline here, not out of line in fast_marching.cpp: a march whose grid comes
// back from a call keeps it in memory and reloads its pointers after every
// queue push (about 15% slower, farm-bench).
inline detail::MarchGrid FastMarching::march_grid(bool labels, int look_back) {
  return detail::MarchGrid{times_.data(),
                           labels ? labels_.data() : nullptr,
                           mask_.data(),
                           cost_.empty() ? nullptr : cost_.data(),
                           unit_cost_,
                           stride_,
                           !inv_front_speed_.empty(),
                           inv_front_speed_.data(),
                           look_back};
}

}  // namespace fmm
}  // namespace gather
