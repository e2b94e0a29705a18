#pragma once
// Collector groups (seed Fig. 2b): the worker segments each collector serves.
#include <vector>

#include "gather_core/ids.hpp"
#include "gather_core/plan/worker_graph.hpp"

namespace gather {
namespace plan {

// Assigns each worker segment to a collector 0..collectors-1, or none = the OC.
// Segments that touch the OC's radio coverage deliver to the OC directly; the
// others are grown into `collectors` groups from the OC outward: seeds are the
// segments nearest the coverage, spread apart; then the group with the least
// estimated work (`work` [s] per segment) takes its adjacent
// unassigned segment nearest the coverage, so groups stay connected and
// balanced. Segments no group can reach through other segments go to the
// group with the nearest centroid (connected through the OC area).
// With collectors == 0 every segment goes to the OC. Deterministic.
PerSegment<CollectorId> group_segments(const WorkerGraph& graph, int collectors, const PerSegment<double>& work);

}  // namespace plan
}  // namespace gather
