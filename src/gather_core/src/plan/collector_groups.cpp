#include "gather_core/plan/collector_groups.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gather {
namespace plan {
namespace {

double centroid_distance(const WorkerSegment& a, const WorkerSegment& b) {
  return std::hypot(a.centroid_m.x - b.centroid_m.x, a.centroid_m.y - b.centroid_m.y);
}

// Nearer the coverage first; ties by id.
bool closer(const WorkerSegment& a, const WorkerSegment& b) {
  return a.coverage_distance != b.coverage_distance ? a.coverage_distance < b.coverage_distance : a.id < b.id;
}

}  // namespace

PerSegment<CollectorId> group_segments(const WorkerGraph& graph, int collectors, const PerSegment<double>& work) {
  PerSegment<CollectorId> out(graph.segments.count());
  if (collectors <= 0) return out;
  std::vector<const WorkerSegment*> candidates;
  for (const WorkerSegment& s : graph.segments)
    if (!s.touches_coverage) candidates.push_back(&s);
  if (candidates.empty()) return out;
  PerSegment<int> group(graph.segments.count(), -1);  // the group (collector) 0.. of each segment, -1 none
  std::sort(candidates.begin(), candidates.end(),
            [](const WorkerSegment* a, const WorkerSegment* b) { return closer(*a, *b); });

  // Seeds: the candidate nearest the coverage, then repeatedly the candidate
  // farthest from the seeds so far among the inner ring (candidates adjacent
  // to a direct segment, or all candidates if the ring is too small).
  PerSegment<uint8_t> direct(graph.segments.count(), 0);
  for (const WorkerSegment& s : graph.segments) direct[s.id] = s.touches_coverage;
  std::vector<const WorkerSegment*> ring;
  for (const WorkerSegment* s : candidates)
    for (SegmentId m : s->neighbours)
      if (direct[m]) {
        ring.push_back(s);
        break;
      }
  if (static_cast<int>(ring.size()) < collectors) ring = candidates;
  const int groups = std::min<int>(collectors, static_cast<int>(candidates.size()));
  std::vector<const WorkerSegment*> seeds{ring.front()};
  while (static_cast<int>(seeds.size()) < groups) {
    const WorkerSegment* far = nullptr;
    double best = -1.0;
    for (const WorkerSegment* s : ring) {
      if (std::find(seeds.begin(), seeds.end(), s) != seeds.end()) continue;
      double d = std::numeric_limits<double>::infinity();
      for (const WorkerSegment* t : seeds) d = std::min(d, centroid_distance(*s, *t));
      if (d > best) best = d, far = s;
    }
    seeds.push_back(far);
  }
  std::vector<double> load(static_cast<std::size_t>(groups), 0.0);
  for (int g = 0; g < groups; ++g) {
    const SegmentId seed = seeds[static_cast<std::size_t>(g)]->id;
    group[seed] = g;
    load[static_cast<std::size_t>(g)] = work[seed];
  }

  // Growth: the least-loaded group that can grow takes its best neighbour.
  std::vector<uint8_t> closed(static_cast<std::size_t>(groups), 0);
  for (;;) {
    int g_best = -1;
    for (int g = 0; g < groups; ++g)
      if (!closed[static_cast<std::size_t>(g)] &&
          (g_best < 0 || load[static_cast<std::size_t>(g)] < load[static_cast<std::size_t>(g_best)]))
        g_best = g;
    if (g_best < 0) break;
    const WorkerSegment* pick = nullptr;
    for (const WorkerSegment& s : graph.segments) {
      if (group[s.id] != g_best) continue;
      for (SegmentId m : s.neighbours) {
        const WorkerSegment& cand = graph.segment(m);
        if (cand.touches_coverage || group[m] >= 0) continue;
        if (!pick || closer(cand, *pick)) pick = &cand;
      }
    }
    if (!pick) {
      closed[static_cast<std::size_t>(g_best)] = 1;
      continue;
    }
    group[pick->id] = g_best;
    load[static_cast<std::size_t>(g_best)] += work[pick->id];
  }
  // Candidates cut off from every group by direct segments.
  for (const WorkerSegment* s : candidates) {
    if (group[s->id] >= 0) continue;
    int g_best = 0;
    double best = std::numeric_limits<double>::infinity();
    for (const WorkerSegment& t : graph.segments) {
      const int g = group[t.id];
      if (g < 0) continue;
      const double d = centroid_distance(*s, t);
      if (d < best) best = d, g_best = g;
    }
    group[s->id] = g_best;
  }
  for (const WorkerSegment& s : graph.segments) out[s.id] = CollectorId(group[s.id]);
  return out;
}

}  // namespace plan
}  // namespace gather
