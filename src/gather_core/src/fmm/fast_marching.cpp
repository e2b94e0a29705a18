// The FMM workspace (FastMarching): binding to a map, speed maps, seeding the
// sources, solve()'s checks and its dispatch to a march, and the queries on the
// result. The marches live in bucket_march.cpp and heap_march.cpp, their
// shared update in stencil.hpp.
#include "gather_core/fmm/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>

#include "gather_core/error.hpp"
#include "stencil.hpp"

namespace gather {
namespace fmm {
namespace {

using detail::kInf;

std::string cell_text(Cell c) { return "(" + std::to_string(c.row) + ", " + std::to_string(c.col) + ")"; }

}  // namespace

FastMarching::FastMarching(const OccupancyGrid& grid) { bind(grid.frame(), grid.free_mask()); }

void FastMarching::bind(const GridFrame& frame, const std::vector<uint8_t>& free) {
  if (frame.width <= 0 || frame.height <= 0 || !(frame.resolution > 0.0))
    throw Error("fmm", "a grid of " + std::to_string(frame.width) + " x " + std::to_string(frame.height) +
                           " cells at " + std::to_string(frame.resolution) + " m (needs cells and a resolution > 0)");
  if (free.size() != frame.size())
    throw Error("fmm",
                "free mask of " + std::to_string(free.size()) + " cells for a grid of " + std::to_string(frame.size()));
  const std::size_t stride = static_cast<std::size_t>(frame.width) + 2 * kPad;
  const std::size_t rows = static_cast<std::size_t>(frame.height) + 2 * kPad;
  if (rows * stride >= std::numeric_limits<uint32_t>::max())
    throw Error(
        "fmm", "grid of " + std::to_string(frame.width) + " x " + std::to_string(frame.height) + " cells is too large");
  width_ = frame.width, height_ = frame.height, stride_ = stride;
  resolution_ = frame.resolution, origin_ = frame.origin;
  mask_.assign(rows * stride_, 0);
  for (int r = 0; r < height_; ++r) {
    const uint8_t* in = &free[static_cast<std::size_t>(r) * static_cast<std::size_t>(width_)];
    uint8_t* out = &mask_[padded(Cell{r, 0})];
    for (int c = 0; c < width_; ++c) out[c] = in[c] != 0 ? 1 : 0;
  }
  // Nothing of the last solve is valid on the new grid: sized again by the next solve.
  times_.clear();
  labels_.clear();
  labels_on_ = false;
  touched_.clear();
  touched_overflow_ = true;
  seeds_.clear();
  sources_.clear();
  stats_ = SolveStats{};
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

void FastMarching::set_speed(const Raster<double>& speed) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  require_same_size(speed, frame(), "fast marching", "the speed map");
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
        throw Error(where,
                    "point [" + std::to_string(s.point.x) + ", " + std::to_string(s.point.y) + "] m is off the map");
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
    const float base_cost = cost_at(padded(base)) * (inv_front_speed_.empty() ? 1.0f : inv_front_speed_[i]);
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell n{base.row + dr, base.col + dc};
        if (!traversable(n)) continue;
        // A diagonal cell is in straight sight only when both cells between are free.
        if (dr != 0 && dc != 0 &&
            (!traversable(Cell{base.row + dr, base.col}) || !traversable(Cell{base.row, base.col + dc})))
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
  if (options.order != Order::kFirst && options.order != Order::kSecond) throw Error("fmm", "order must be 1 or 2");
  if (!(options.bucket_width >= 0.0) || !std::isfinite(options.bucket_width))
    throw Error("fmm", "bucket_width must be >= 0");
  if (std::isnan(options.max_time) || options.max_time < 0.0) throw Error("fmm", "max_time must be >= 0");
  if (options.label_look_back < 0 || options.label_look_back > 64)
    throw Error("fmm", "label_look_back must be in 0..64 cells");
  targets_.clear();
  for (std::size_t i = 0; i < options.targets.size(); ++i) {
    const Cell c = options.targets[i];
    if (!contains(c)) throw Error("target " + std::to_string(i), "cell " + cell_text(c) + " is off the map");
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
  const March march = queue == QueueKind::kHeap ? heap_march(unit, lab, second)
                                                : bucket_march(unit, lab, second, queue == QueueKind::kSortedBuckets);
  (this->*march)(options);

  return stats_;
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

Raster<double> FastMarching::times() const {
  Raster<double> out;
  copy_times(out);
  return out;
}

LabelImage FastMarching::labels() const {
  LabelImage out;
  copy_labels(out);
  return out;
}

void FastMarching::copy_times(Raster<double>& out) const {
  if (out.frame() != frame() || !out.filled()) out = Raster<double>(frame());
  for (int r = 0; r < height_; ++r) {
    const float* row = times_.empty() ? nullptr : &times_[padded(Cell{r, 0})];
    double* o = &out[static_cast<std::size_t>(r) * width_];
    for (int c = 0; c < width_; ++c) o[c] = row && row[c] < kInf ? static_cast<double>(row[c]) : kUnreached;
  }
}

void FastMarching::copy_labels(LabelImage& out) const {
  if (out.frame() != frame() || !out.filled()) out = LabelImage(frame());
  std::fill(out.begin(), out.end(), -1);
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
                  heap_.capacity() * sizeof(HeapEntry) + (sorted_.capacity() + bheap_.capacity()) * sizeof(uint64_t) +
                  inv_front_speed_.capacity() * sizeof(float) + late_.capacity() * sizeof(uint32_t) +
                  targets_.capacity() * sizeof(uint32_t) + seeds_.capacity() * sizeof(Seed) +
                  sources_.capacity() * sizeof(Source);
  for (const auto& v : buckets_) b += v.capacity() * sizeof(uint32_t) + sizeof(std::vector<uint32_t>);
  return b;
}

}  // namespace fmm
}  // namespace gather
