#include "gather_core/mission/repair.hpp"

#include <algorithm>
#include <limits>

#include "gather_core/error.hpp"
#include "gather_core/input_file.hpp"

namespace gather {
namespace mission {

const char* repair_mode_name(RepairMode m) { return m == RepairMode::kMerge ? "merge" : "none"; }

RepairMode parse_repair_mode(const std::string& text, const std::string& where) {
  if (text == "merge") return RepairMode::kMerge;
  if (text == "none") return RepairMode::kNone;
  throw Error(where, "must be merge or none, got '" + quote_input(text) + "'");
}

RepairedPlan repair_plan(const MissionPlan& base, const std::vector<AgentId>& dead, RepairMode mode) {
  RepairedPlan out;
  out.plan = base;
  const int n = static_cast<int>(base.file.agents.size());
  const int segments = base.file.workers;
  out.dead.assign(n, 0);
  for (AgentId a : dead)
    if (a.within(n)) out.dead[a] = 1;
  // Owner of each label as it is now (labels only ever name live workers'
  // segments or dead workers not yet merged); by label, 0 = no segment.
  std::vector<AgentId> owner(static_cast<std::size_t>(segments) + 1);
  for (const plan::AgentAssignment& a : base.file.agents)
    if (!a.collector && a.segment.within(segments)) owner[static_cast<std::size_t>(a.segment.label())] = a.id;
  LabelImage& labels = out.plan.labels;
  const int w = labels.width(), h = labels.height();
  if (!labels.filled()) throw RuntimeError("plan repair (internal error)", "label image size");
  std::vector<int64_t> cells(static_cast<std::size_t>(segments) + 1, 0);
  for (int32_t l : labels)
    if (l >= 1 && l <= segments) ++cells[static_cast<std::size_t>(l)];
  // Which label stands for each original segment (itself until merged).
  std::vector<int> now_label(static_cast<std::size_t>(segments) + 1);
  for (int s = 0; s <= segments; ++s) now_label[static_cast<std::size_t>(s)] = s;

  // Collectors first; then the dead workers, in passes: one whose segment
  // touches no live worker's now may touch one after a neighbour merged.
  std::vector<AgentId> waiting;  // dead workers whose segment is not merged yet
  for (AgentId a : ids<AgentId>(n)) {
    if (!out.dead[a]) continue;
    const plan::AgentAssignment& dying = base.file.agents[a];
    if (dying.collector) {
      for (plan::AgentAssignment& x : out.plan.file.agents)
        if (!x.collector && x.delivers_to == dying.delivers_to) x.delivers_to = CollectorId();
    } else if (dying.segment.within(segments)) {
      waiting.push_back(a);
    }
  }
  auto relabel = [&](int32_t s, int32_t into) {
    for (int32_t& l : labels)
      if (l == s) l = into;
    cells[static_cast<std::size_t>(into)] += cells[static_cast<std::size_t>(s)];
    cells[static_cast<std::size_t>(s)] = 0;
    for (int seg = 1; seg <= segments; ++seg)
      if (now_label[static_cast<std::size_t>(seg)] == s) now_label[static_cast<std::size_t>(seg)] = into;
  };
  // The live workers' segment with the fewest cells that touches label s (0: none).
  auto neighbour = [&](int32_t s) {
    std::vector<uint8_t> touches(static_cast<std::size_t>(segments) + 1, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (labels[static_cast<std::size_t>(y) * w + x] != s) continue;
        const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
        for (int k = 0; k < 4; ++k) {
          if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
          const int32_t l = labels[static_cast<std::size_t>(ny[k]) * w + nx[k]];
          if (l >= 1 && l <= segments && l != s) touches[static_cast<std::size_t>(l)] = 1;
        }
      }
    int32_t into = 0;
    int64_t best = std::numeric_limits<int64_t>::max();
    for (int l = 1; l <= segments; ++l) {
      const AgentId o = owner[static_cast<std::size_t>(l)];
      if (!touches[static_cast<std::size_t>(l)] || !o.valid() || out.dead[o]) continue;
      if (cells[static_cast<std::size_t>(l)] < best) best = cells[static_cast<std::size_t>(l)], into = l;
    }
    return into;
  };
  if (mode == RepairMode::kMerge) {
    for (bool merged = true; merged && !waiting.empty();) {
      merged = false;
      for (std::size_t k = 0; k < waiting.size();) {
        const int32_t s = now_label[static_cast<std::size_t>(base.file.agents[waiting[k]].segment.label())];
        const int32_t into = neighbour(s);
        if (into > 0) {
          relabel(s, into);
          waiting.erase(waiting.begin() + static_cast<long>(k));
          merged = true;
        } else {
          ++k;
        }
      }
    }
  }
  for (AgentId a : waiting) {  // no live neighbour, or kNone: nobody serves it
    const int32_t s = now_label[static_cast<std::size_t>(base.file.agents[a].segment.label())];
    if (s >= 1) relabel(s, 0);
  }
  out.worker_of_segment = PerSegment<AgentId>(segments);
  for (SegmentId seg : segment_ids(segments)) {
    const int l = now_label[static_cast<std::size_t>(seg.label())];
    const AgentId o = l >= 1 ? owner[static_cast<std::size_t>(l)] : AgentId();
    out.worker_of_segment[seg] = o.valid() && !out.dead[o] ? o : AgentId();
  }
  return out;
}

double silent_timeout(Liveness kind, double period, double route_period, double intervals) {
  switch (kind) {
    case Liveness::kCollector: return intervals * route_period;
    case Liveness::kOcWorker: return intervals * period;
    case Liveness::kCollectorWorker: return intervals * (route_period + period);
  }
  return intervals * period;
}

}  // namespace mission
}  // namespace gather
