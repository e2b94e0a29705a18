#include "gather_core/partition/front_growth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/error.hpp"

namespace gather {
namespace partition {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint8_t kFar = 0, kBand = 1, kAccepted = 2, kPinned = 3, kBlocked = 4;

template <class E>
bool later(const E& a, const E& b) { return a.t > b.t || (a.t == b.t && a.p > b.p); }

}  // namespace

FrontGrowth::FrontGrowth(int width, int height, double resolution, const std::vector<uint8_t>& region)
    : width_(width), height_(height), stride_(static_cast<std::size_t>(width) + 2), res_(static_cast<float>(resolution)) {
  if (width <= 0 || height <= 0 || region.size() != static_cast<std::size_t>(width) * height)
    throw Error("partition", "front growth: region mask does not match the map size");
  const std::size_t n = stride_ * (static_cast<std::size_t>(height) + 2);
  region_.assign(n, 0);
  for (std::size_t i = 0; i < region.size(); ++i) region_[pad(i)] = region[i] ? 1 : 0;
  avail_ = region_;
  visit_.assign(n, 0);
  tried_.assign(n, 0);
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

void FrontGrowth::push(float t, uint32_t p) {
  heap_.push_back(Entry{t, p});
  std::push_heap(heap_.begin(), heap_.end(), [](const Entry& a, const Entry& b) { return later(a, b); });
}

void FrontGrowth::reset_touched() {
  for (uint32_t p : touched_) {
    time_[p] = kInf;
    state_[p] = kFar;
    tried_[p] = 0;
  }
  touched_.clear();
  heap_.clear();
}

float FrontGrowth::update(std::size_t p, int32_t label) const {
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
  if (confine && confine->size() != n) throw Error("partition", "front growth: confine map does not match the map size");
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
  const float width = 0.5f * res_ * min_slowness_;
  const std::size_t nbuckets = static_cast<std::size_t>(std::ceil(res_ * max_slowness_ / width)) + 3;
  if (buckets_.size() < nbuckets) buckets_.resize(nbuckets);
  for (auto& b : buckets_) b.clear();
  double base = sources_.front().t;
  std::size_t cur = 0, pending = 0, next_source = 0;
  auto insert = [&](float t, uint32_t p) {
    const double d = (static_cast<double>(t) - base) / width;
    std::size_t idx = d <= 0.0 ? 0 : static_cast<std::size_t>(d);
    if (idx > nbuckets - 2) idx = nbuckets - 2;
    buckets_[(cur + idx) % nbuckets].push_back(p);
    ++pending;
  };
  const std::ptrdiff_t nb[4] = {-1, 1, -static_cast<std::ptrdiff_t>(stride_), static_cast<std::ptrdiff_t>(stride_)};
  for (;;) {
    while (next_source < sources_.size() && sources_[next_source].t < base + width) {
      insert(sources_[next_source].t, sources_[next_source].p);
      ++next_source;
    }
    if (pending == 0) {
      if (next_source == sources_.size()) break;
      base = sources_[next_source].t;  // jump over an empty stretch of time
      continue;
    }
    for (std::size_t i = 0; i < buckets_[cur].size(); ++i) {
      const uint32_t p = buckets_[cur][i];
      --pending;
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
          insert(t, static_cast<uint32_t>(q));
        }
      }
    }
    buckets_[cur].clear();
    cur = (cur + 1) % nbuckets;
    base += width;
  }
  labels.assign(n, 0);
  if (times) times->assign(n, kInf);
  for (uint32_t p : touched_) {
    const std::size_t i = unpad(p);
    labels[i] = label_[p];
    if (times) (*times)[i] = time_[p];
  }
}

void FrontGrowth::lower(std::size_t cell, std::vector<float>& dist) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (cell >= n || !region_[pad(cell)] || dist.size() != n) throw Error("partition", "front growth: bad lower() call");
  reset_touched();
  const std::size_t s = pad(cell);
  label_[s] = -1;
  time_[s] = 0.0f;
  state_[s] = kBand;
  touched_.push_back(static_cast<uint32_t>(s));
  push(0.0f, static_cast<uint32_t>(s));
  const auto cmp = [](const Entry& a, const Entry& b) { return later(a, b); };
  const std::ptrdiff_t nb[4] = {-1, 1, -static_cast<std::ptrdiff_t>(stride_), static_cast<std::ptrdiff_t>(stride_)};
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), cmp);
    const Entry e = heap_.back();
    heap_.pop_back();
    if (state_[e.p] == kAccepted || e.t > time_[e.p]) continue;
    state_[e.p] = kAccepted;
    float& d = dist[unpad(e.p)];
    if (e.t >= d) continue;  // already as close to an earlier source: stop here
    d = e.t;
    for (std::ptrdiff_t o : nb) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(e.p) + o);
      if (!region_[q] || state_[q] == kAccepted) continue;
      const float t = update(q, -1);
      if (t < time_[q]) {
        if (state_[q] == kFar) touched_.push_back(static_cast<uint32_t>(q));
        state_[q] = kBand;
        time_[q] = t;
        label_[q] = -1;
        push(t, static_cast<uint32_t>(q));
      }
    }
  }
  for (uint32_t p : touched_) label_[p] = 0;
}

void FrontGrowth::reset_available() { avail_ = region_; }

bool FrontGrowth::removable_padded(std::size_t p) const {
  // The 8-neighbourhood as a cycle N, NE, E, SE, S, SW, W, NW: consecutive cells
  // share an edge, so available cells in one run are 4-connected without p.
  const std::ptrdiff_t s = static_cast<std::ptrdiff_t>(stride_);
  const std::ptrdiff_t ring[8] = {s, s + 1, 1, -s + 1, -s, -s - 1, -1, s - 1};
  bool in[8];
  int count = 0;
  for (int k = 0; k < 8; ++k) {
    in[k] = avail_[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + ring[k])] != 0;
    count += in[k];
  }
  if (count == 8) return true;
  // Runs that hold a 4-neighbour (even positions); start after an unavailable cell.
  int start = 0;
  while (in[start]) ++start;
  int runs_with_edge = 0;
  bool in_run = false, has_edge = false;
  for (int j = 1; j <= 8; ++j) {
    const int k = (start + j) % 8;
    if (in[k]) {
      if (!in_run) in_run = true, has_edge = false;
      if (k % 2 == 0) has_edge = true;
    } else if (in_run) {
      in_run = false;
      runs_with_edge += has_edge;
    }
  }
  return runs_with_edge <= 1;
}

std::size_t FrontGrowth::resolve_cut(std::size_t p, std::size_t budget, int32_t label, std::vector<int32_t>& labels,
                                     float t) {
  const std::ptrdiff_t st = static_cast<std::ptrdiff_t>(stride_);
  const std::ptrdiff_t nb[4] = {-1, 1, -st, st};
  std::size_t absorbed = 0;
  pocket_.clear();
  for (int round = 0; round < 4 && !removable_padded(p); ++round) {
    // The available 4-neighbours of p: one per side of the cut (at most 4).
    std::size_t reps[4];
    int nreps = 0;
    for (std::ptrdiff_t o : nb) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + o);
      if (avail_[q]) reps[nreps++] = q;
    }
    bool progressed = false;
    for (int a = 0; a < nreps && !progressed; ++a) {
      // Breadth-first search from one side, p excluded, up to `budget` cells.
      ++stamp_;
      if (stamp_ == 0) std::fill(visit_.begin(), visit_.end(), 0), stamp_ = 1;
      visit_[p] = stamp_;
      bfs_.assign(1, static_cast<uint32_t>(reps[a]));
      visit_[reps[a]] = stamp_;
      std::size_t head = 0, weight = cell_weight(reps[a]);
      bool over = false;
      int found = 1;
      while (head < bfs_.size() && found < nreps) {
        if (weight > budget || bfs_.size() > kMaxPocketSearch) {
          over = true;
          break;
        }
        const std::size_t c = bfs_[head++];
        for (std::ptrdiff_t o : nb) {
          const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + o);
          if (avail_[q] && visit_[q] != stamp_) {
            visit_[q] = stamp_;
            bfs_.push_back(static_cast<uint32_t>(q));
            weight += cell_weight(q);
            for (int b = 0; b < nreps; ++b) found += q == reps[b];
          }
        }
      }
      if (found == nreps) return absorbed;  // every side meets every other: p is no cut
      if (over) continue;
      // A closed pocket that fits: it joins this segment.
      for (uint32_t c : bfs_) pocket_.push_back(Saved{c, state_[c], time_[c]});
      for (uint32_t c : bfs_) {
        avail_[c] = 0;
        if (state_[c] == kFar) touched_.push_back(c);
        state_[c] = kAccepted;
        time_[c] = t;
        label_[c] = label;
        labels[unpad(c)] = label;
      }
      absorbed += weight;
      budget -= std::min(budget, weight);
      progressed = true;
    }
    if (!progressed) break;
  }
  if (removable_padded(p)) return absorbed;
  // Not resolved: give the pockets taken on the way back.
  for (std::size_t k = pocket_.size(); k-- > 0;) {
    const uint32_t c = pocket_[k].p;
    avail_[c] = 1;
    state_[c] = pocket_[k].state;
    time_[c] = pocket_[k].t;
    labels[unpad(c)] = 0;
  }
  return kCutBlocked;
}

std::size_t FrontGrowth::grow_quota(std::size_t seed, std::size_t quota, int32_t label, std::vector<int32_t>& labels) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (seed >= n || !avail_[pad(seed)]) throw Error("partition", "front growth: quota seed is not available");
  if (labels.size() != n) labels.assign(n, 0);
  reset_touched();
  const std::size_t s = pad(seed);
  time_[s] = 0.0f;
  state_[s] = kBand;
  touched_.push_back(static_cast<uint32_t>(s));
  push(0.0f, static_cast<uint32_t>(s));
  const auto cmp = [](const Entry& a, const Entry& b) { return later(a, b); };
  const std::ptrdiff_t st = static_cast<std::ptrdiff_t>(stride_);
  const std::ptrdiff_t nb[4] = {-1, 1, -st, st};
  const std::ptrdiff_t ring[8] = {st, st + 1, 1, -st + 1, -st, -st - 1, -1, st - 1};
  std::size_t taken = 0;
  bool first = true;
  while (!heap_.empty() && taken < quota) {
    std::pop_heap(heap_.begin(), heap_.end(), cmp);
    const Entry e = heap_.back();
    heap_.pop_back();
    if (state_[e.p] == kAccepted || state_[e.p] == kBlocked || e.t > time_[e.p] || !avail_[e.p]) continue;
    if (!first && !removable_padded(e.p)) {
      // A local cut: take it if its sides meet elsewhere, or if one side is a
      // pocket small enough to absorb into this segment; else wait.
      // A cell whose search failed is searched again only after the front
      // has grown by kRetryCells.
      const bool retry = tried_[e.p] == 0 || taken + 1 >= tried_[e.p] + kRetryCells;
      const std::size_t need = quota - taken;
      const std::size_t pocket_budget = need > cell_weight(e.p) ? need - cell_weight(e.p) : 0;
      const std::size_t absorbed = retry ? resolve_cut(e.p, pocket_budget, label, labels, e.t) : kCutBlocked;
      if (absorbed == kCutBlocked) {
        if (retry) tried_[e.p] = static_cast<uint32_t>(taken + 1);
        state_[e.p] = kBlocked;  // re-queued when a neighbour is taken
        continue;
      }
      taken += absorbed;
    }
    first = false;
    state_[e.p] = kAccepted;
    avail_[e.p] = 0;
    label_[e.p] = label;
    labels[unpad(e.p)] = label;
    taken += cell_weight(e.p);
    for (std::ptrdiff_t o : ring) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(e.p) + o);
      if (state_[q] == kBlocked) {
        state_[q] = kBand;
        push(time_[q], static_cast<uint32_t>(q));
      }
    }
    for (std::ptrdiff_t o : nb) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(e.p) + o);
      if (!avail_[q] || state_[q] == kAccepted) continue;
      const float t = update(q, label);
      if (t < time_[q]) {
        if (state_[q] == kFar) touched_.push_back(static_cast<uint32_t>(q));
        if (state_[q] != kBlocked) state_[q] = kBand;
        time_[q] = t;
        if (state_[q] == kBand) push(t, static_cast<uint32_t>(q));
      }
    }
  }
  for (uint32_t p : touched_) label_[p] = 0;
  return taken;
}

void FrontGrowth::release(int32_t label, std::vector<int32_t>& labels) {
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == label) labels[i] = 0, avail_[pad(i)] = 1;
}

std::size_t FrontGrowth::take_rest(int32_t label, std::vector<int32_t>& labels) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  if (labels.size() != n) labels.assign(n, 0);
  std::size_t taken = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = pad(i);
    if (!avail_[p]) continue;
    avail_[p] = 0;
    labels[i] = label;
    taken += cell_weight(p);
  }
  return taken;
}

}  // namespace partition
}  // namespace gather
