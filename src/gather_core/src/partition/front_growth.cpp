#include "gather_core/partition/front_growth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/error.hpp"
#include "gather_core/numeric.hpp"

namespace gather {
namespace partition {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint8_t kFar = 0, kBand = 1, kAccepted = 2, kPinned = 3;

template <class E>
bool later(const E& a, const E& b) {
  return a.t > b.t || (a.t == b.t && a.p > b.p);
}

// The untidy bucket queue of grow() and grow_quota(): a ring of buckets half
// the cheapest cell crossing wide, FIFO inside a bucket; O(1) per insert.
// The caller drains current() by index (inserts may append to it), then
// calls advance().
class BucketRing {
 public:
  BucketRing(std::vector<std::vector<uint32_t>>& buckets, float res, float min_slowness, float max_slowness,
             double base)
      : buckets_(buckets), width_(0.5f * res * min_slowness), base_(base) {
    n_ = static_cast<std::size_t>(std::ceil(res * max_slowness / width_)) + 3;
    inv_width_ = 1.0 / static_cast<double>(width_);
    if (buckets_.size() < n_) buckets_.resize(n_);
    for (auto& b : buckets_) b.clear();
  }
  void insert(float t, uint32_t p) {
    const double d = (static_cast<double>(t) - base_) * inv_width_;
    std::size_t idx = d <= 0.0 ? 0 : static_cast<std::size_t>(d);
    if (idx > n_ - 2) idx = n_ - 2;
    std::size_t j = cur_ + idx;  // < 2 n: no division in this hot path
    if (j >= n_) j -= n_;
    buckets_[j].push_back(p);
    ++pending_;
  }
  std::vector<uint32_t>& current() { return buckets_[cur_]; }
  void taken() { --pending_; }  // one entry of current() consumed
  void advance() {
    buckets_[cur_].clear();
    if (++cur_ == n_) cur_ = 0;
    base_ += width_;
  }
  std::size_t pending() const { return pending_; }
  double base() const { return base_; }
  float width() const { return width_; }
  void jump_to(double base) { base_ = base; }  // only while nothing is pending

 private:
  std::vector<std::vector<uint32_t>>& buckets_;
  float width_;
  double base_;
  double inv_width_ = 1.0;
  std::size_t n_ = 0, cur_ = 0, pending_ = 0;
};

}  // namespace

FrontGrowth::FrontGrowth(const Mask& region)
    : width_(region.width()),
      height_(region.height()),
      stride_(static_cast<std::size_t>(region.width()) + 2),
      res_(static_cast<float>(region.frame().resolution)) {
  const int width = width_, height = height_;
  if (width <= 0 || height <= 0 || !region.filled())
    throw Error("partition", "front growth: the region mask is empty or holds no value per cell");
  const std::size_t n = stride_ * (static_cast<std::size_t>(height) + 2);
  region_.assign(n, 0);
  for (int r = 0; r < height; ++r) {
    const uint8_t* src = region.data() + static_cast<std::size_t>(r) * width;
    uint8_t* dst = region_.data() + (static_cast<std::size_t>(r) + 1) * stride_ + 1;
    for (int c = 0; c < width; ++c) dst[c] = src[c] ? 1 : 0;
  }
  avail_ = region_;
  time_.assign(n, kInf);
  label_.assign(n, 0);
  state_.assign(n, kFar);
}

void FrontGrowth::set_slowness(const std::vector<float>& slowness) {
  if (slowness.empty()) {
    slowness_.clear();
    min_slowness_ = max_slowness_ = 1.0f;
    return;
  }
  if (slowness.size() != static_cast<std::size_t>(width_) * height_)
    throw Error("partition", "front growth: slowness map does not match the map size");
  slowness_.assign(region_.size(), 1.0f);
  min_slowness_ = std::numeric_limits<float>::infinity();
  max_slowness_ = 0.0f;
  for (std::size_t i = 0; i < slowness.size(); ++i) {
    if (!(slowness[i] > 0.0f) || !std::isfinite(slowness[i]))
      throw Error("partition", "front growth: slowness must be finite and > 0");
    slowness_[pad(i)] = slowness[i];
    min_slowness_ = std::min(min_slowness_, slowness[i]);
    max_slowness_ = std::max(max_slowness_, slowness[i]);
  }
}

void FrontGrowth::set_weights(const std::vector<uint32_t>& weights) {
  if (weights.empty()) {
    weight_.clear();
    return;
  }
  if (weights.size() != static_cast<std::size_t>(width_) * height_)
    throw Error("partition", "front growth: weight map does not match the map size");
  weight_.assign(region_.size(), 0);
  for (std::size_t i = 0; i < weights.size(); ++i) weight_[pad(i)] = weights[i];
}

void FrontGrowth::reset_touched() {
  for (uint32_t p : touched_) {
    time_[p] = kInf;
    state_[p] = kFar;
  }
  touched_.clear();
  queue_.clear();
}

inline float FrontGrowth::update(std::size_t p, int32_t label) const {
  auto val = [&](std::size_t q) { return state_[q] == kAccepted && label_[q] == label ? time_[q] : kInf; };
  float a = std::min(val(p - 1), val(p + 1));
  float b = std::min(val(p - stride_), val(p + stride_));
  if (a > b) std::swap(a, b);
  const float h = cost(p);
  if (!(b - a < h)) return a + h;  // also b = +inf
  const float d = a - b;
  return 0.5f * (a + b + std::sqrt(2.0f * h * h - d * d));
}

void FrontGrowth::grow(const std::vector<Front>& fronts, std::vector<int32_t>& labels, std::vector<float>* times,
                       const std::vector<int32_t>* confine) {
  if (fronts.empty()) throw Error("partition", "front growth: no fronts");
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (confine && confine->size() != n)
    throw Error("partition", "front growth: confine map does not match the map size");
  reset_touched();
  std::fill(label_.begin(), label_.end(), 0);
  for (std::size_t k = 0; k < fronts.size(); ++k) {
    if (fronts[k].cell >= n || !region_[pad(fronts[k].cell)])
      throw Error("partition", "front growth: front " + std::to_string(k) + " starts outside the region");
    const std::size_t p = pad(fronts[k].cell);
    const float t = static_cast<float>(fronts[k].start);
    if (state_[p] == kPinned && time_[p] <= t) continue;
    if (state_[p] == kFar) touched_.push_back(static_cast<uint32_t>(p));
    time_[p] = t;
    label_[p] = static_cast<int32_t>(k) + 1;
    state_[p] = kPinned;
  }
  // Untidy bucket queue (buckets of half the cheapest cell crossing, FIFO
  // inside a bucket, each cell accepted once): O(1) per cell, times within
  // about a bucket width of exact FMM; a cell still takes its label from an
  // accepted neighbour, so labels stay connected.
  sources_.clear();
  for (uint32_t p : touched_) sources_.push_back(Entry{time_[p], p});
  std::sort(sources_.begin(), sources_.end(), [](const Entry& a, const Entry& b) { return later(b, a); });
  BucketRing ring(buckets_, res_, min_slowness_, max_slowness_, sources_.front().t);
  std::size_t next_source = 0;
  const std::ptrdiff_t nb[4] = {-1, 1, -static_cast<std::ptrdiff_t>(stride_), static_cast<std::ptrdiff_t>(stride_)};
  for (;;) {
    while (next_source < sources_.size() && sources_[next_source].t < ring.base() + ring.width()) {
      ring.insert(sources_[next_source].t, sources_[next_source].p);
      ++next_source;
    }
    if (ring.pending() == 0) {
      if (next_source == sources_.size()) break;
      ring.jump_to(sources_[next_source].t);  // jump over an empty stretch of time
      continue;
    }
    std::vector<uint32_t>& bucket = ring.current();
    for (std::size_t i = 0; i < bucket.size(); ++i) {
      const uint32_t p = bucket[i];
      ring.taken();
      if (state_[p] == kAccepted) continue;
      state_[p] = kAccepted;
      const int32_t lab = label_[p];
      for (std::ptrdiff_t o : nb) {
        const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + o);
        if (!region_[q] || state_[q] == kAccepted || state_[q] == kPinned) continue;
        if (confine && (*confine)[unpad(q)] != lab) continue;
        const float t = update(q, lab);
        if (t < time_[q]) {
          if (state_[q] == kFar) touched_.push_back(static_cast<uint32_t>(q));
          state_[q] = kBand;
          time_[q] = t;
          label_[q] = lab;
          ring.insert(t, static_cast<uint32_t>(q));
        }
      }
    }
    ring.advance();
  }
  labels.assign(n, 0);
  if (times) times->assign(n, kInf);
  for (uint32_t p : touched_) {
    const std::size_t i = unpad(p);
    labels[i] = label_[p];
    if (times) (*times)[i] = time_[p];
  }
}

void FrontGrowth::lower(std::size_t cell, std::vector<float>& dist, std::vector<uint32_t>* lowered) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (cell >= n || !region_[pad(cell)] || dist.size() != n) throw Error("partition", "front growth: bad lower() call");
  reset_touched();
  if (lowered) lowered->clear();
  const std::size_t s = pad(cell);
  label_[s] = -1;
  time_[s] = 0.0f;
  state_[s] = kBand;
  touched_.push_back(static_cast<uint32_t>(s));
  queue_.clear();
  queue_.push(order_key(0.0f, static_cast<uint32_t>(s)));
  const std::ptrdiff_t nb[4] = {-1, 1, -static_cast<std::ptrdiff_t>(stride_), static_cast<std::ptrdiff_t>(stride_)};
  while (!queue_.empty()) {
    const uint64_t k = queue_.pop();
    const Entry e{time_[static_cast<uint32_t>(k)], static_cast<uint32_t>(k)};
    if (state_[e.p] == kAccepted || k != order_key(e.t, e.p)) continue;  // taken, or improved since
    state_[e.p] = kAccepted;
    const std::size_t cell_at = unpad(e.p);
    float& d = dist[cell_at];
    if (e.t >= d) continue;  // already as close to an earlier source: stop here
    d = e.t;
    if (lowered) lowered->push_back(static_cast<uint32_t>(cell_at));
    for (std::ptrdiff_t o : nb) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(e.p) + o);
      if (!region_[q] || state_[q] == kAccepted) continue;
      const float t = update(q, -1);
      if (t < time_[q]) {
        if (state_[q] == kFar) touched_.push_back(static_cast<uint32_t>(q));
        state_[q] = kBand;
        time_[q] = t;
        label_[q] = -1;
        queue_.push(order_key(t, static_cast<uint32_t>(q)));
      }
    }
  }
  for (uint32_t p : touched_) label_[p] = 0;
}

void FrontGrowth::reset_available() { avail_ = region_; }

std::size_t FrontGrowth::grow_quota(std::size_t seed, std::size_t quota, int32_t label, std::vector<int32_t>& labels,
                                    std::vector<uint32_t>* taken_cells) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (taken_cells) taken_cells->clear();
  if (seed >= n || !avail_[pad(seed)]) throw Error("partition", "front growth: quota seed is not available");
  if (labels.size() != n) labels.assign(n, 0);
  reset_touched();
  const std::size_t s = pad(seed);
  time_[s] = 0.0f;
  state_[s] = kBand;
  touched_.push_back(static_cast<uint32_t>(s));
  // The untidy bucket queue of grow(): O(1) per cell; a cell is accepted
  // once, from an accepted neighbour of this front, so the front is
  // 4-connected.
  BucketRing ring(buckets_, res_, min_slowness_, max_slowness_, 0.0);
  ring.insert(0.0f, static_cast<uint32_t>(s));
  const std::ptrdiff_t st = static_cast<std::ptrdiff_t>(stride_);
  const std::ptrdiff_t nb[4] = {-1, 1, -st, st};
  std::size_t taken = 0;
  while (ring.pending() > 0 && taken < quota) {
    std::vector<uint32_t>& bucket = ring.current();
    for (std::size_t i = 0; i < bucket.size() && taken < quota; ++i) {
      const uint32_t p = bucket[i];
      ring.taken();
      if (state_[p] == kAccepted) continue;
      state_[p] = kAccepted;
      avail_[p] = 0;
      label_[p] = label;
      labels[unpad(p)] = label;
      taken += cell_weight(p);
      if (taken_cells) taken_cells->push_back(static_cast<uint32_t>(unpad(p)));
      for (std::ptrdiff_t o : nb) {
        const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + o);
        if (!avail_[q] || state_[q] == kAccepted) continue;
        const float t = update(q, label);
        if (t < time_[q]) {
          if (state_[q] == kFar) touched_.push_back(static_cast<uint32_t>(q));
          state_[q] = kBand;
          time_[q] = t;
          ring.insert(t, static_cast<uint32_t>(q));
        }
      }
    }
    if (taken >= quota) break;
    ring.advance();
  }
  for (uint32_t p : touched_) label_[p] = 0;
  return taken;
}

std::size_t FrontGrowth::take_rest(int32_t label, std::vector<int32_t>& labels) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (labels.size() != n) labels.assign(n, 0);
  std::size_t taken = 0;
  for (int r = 0; r < height_; ++r) {
    const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(width_);
    const std::size_t prow = (static_cast<std::size_t>(r) + 1) * stride_ + 1;
    for (int c = 0; c < width_; ++c) {
      const std::size_t p = prow + static_cast<std::size_t>(c);
      if (!avail_[p]) continue;
      avail_[p] = 0;
      labels[row + static_cast<std::size_t>(c)] = label;
      taken += cell_weight(p);
    }
  }
  return taken;
}

}  // namespace partition
}  // namespace gather
