#pragma once
// A collector's closed route through the entry cells of its segments:
// geodesic legs from FMM (A* on the grid where a leg must squeeze through),
// the visiting order by an exact or a 2-opt tour, polished with OMPL.
#include <cstdint>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// Collector `collector`'s route through `segments` (ids, ascending) of
// `graph` (`labels`: the partition's labels). `fm`: a march workspace on the
// route speed map (a copy of ctx.oc_field), reused from route to route. A
// collector without segments stays at the OC (one waypoint).
CollectorRoute build_route(const PlanContext& ctx, fmm::FastMarching& fm, const WorkerGraph& graph,
                           const LabelImage& labels, const std::vector<SegmentId>& segments, CollectorId collector,
                           const PlannerOptions& opt);

}  // namespace plan
}  // namespace gather
