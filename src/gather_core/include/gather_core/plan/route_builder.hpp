#pragma once
// A collector's closed route through the entry cells of its segments:
// geodesic legs from FMM (A* on the grid where a leg must squeeze through),
// the visiting order by an exact or a 2-opt tour, polished with OMPL.
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/path/path_polisher.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// The polished legs of routes built on one partition, by the cells of their
// two stops (kOcStop: the OC): a leg depends on nothing else, and a route
// rebuilt with a stop less (the association's trials) keeps most of its
// legs. Within one configuration (one thread).
struct LegCache {
  static constexpr std::size_t kOcStop = static_cast<std::size_t>(-1);
  std::map<std::pair<std::size_t, std::size_t>, PolishedPath> legs;
};

// Collector `collector`'s route through `segments` (ids, ascending) of
// `graph` (`labels`: the partition's labels). `fm`: a march workspace on the
// route speed map (a copy of ctx.oc_field), reused from route to route;
// `legs` (optional): legs built before on the same partition, and where the
// new ones are kept. A collector without segments stays at the OC (one
// waypoint).
CollectorRoute build_route(const PlanContext& ctx, fmm::FastMarching& fm, const WorkerGraph& graph,
                           const LabelImage& labels, const std::vector<SegmentId>& segments, CollectorId collector,
                           const PlannerOptions& opt, LegCache* legs = nullptr);

}  // namespace plan
}  // namespace gather
