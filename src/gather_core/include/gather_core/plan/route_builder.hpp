#pragma once
// A collector's closed route through the entry cells of its segments:
// geodesic legs from FMM (A* on the grid where a leg must squeeze through),
// the visiting order by an exact or a 2-opt tour, polished with OMPL.
#include <cstdint>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/path/path_polisher.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// Landmarks for the A* of the legs between meeting areas (ALT: the
// triangle inequality bounds the cost from a cell to the leg's end by
// |d_L(cell) - d_L(end)| for every landmark L, a far tighter bound than the
// straight line where walls make the way long). The cost of every cell from
// each landmark, on the legs' own 8-connected graph, is searched once per
// sweep, on the first leg's need (PlanContext::use_leg_landmarks: teams of
// PlannerOptions::leg_landmarks_team robots or more). Thread-safe.
struct LegLandmarks {
  // Landmarks per cell; the first is the OC's cell, each next the cell
  // farthest from those before.
  static constexpr int kCount = 6;
  std::once_flag once;
  std::vector<float> cost;  // [cell * kCount + l]: the legs' cost (cells) from landmark l, +inf unreached
};

// The A* paths of the legs between meeting areas, by their two cells, kept
// for the sweep: a leg's path depends on nothing but its two cells and the
// context, and configurations share meeting areas (intel_map's sweep
// searches 58 legs, 40 of them distinct). At most kBytes of cells kept
// (then the legs are searched each time). Thread-safe. The paths hold for
// the context that searched them: a copy of a PlanContext shares them, and
// must not change its masks or use_leg_landmarks.
struct LegPaths {
  static constexpr std::size_t kBytes = std::size_t{4} << 20;
  std::mutex mutex;
  std::size_t bytes = 0;
  std::size_t searched = 0;  // the legs searched, not found kept
  // start and goal cell -> the path's cells from start to goal (empty: the
  // goal is not reached).
  std::map<std::pair<std::size_t, std::size_t>, std::vector<uint32_t>> cells;
};

// The cost (in cells: a straight step between two roomy cells costs 1) of
// the A* leg from a to b (as a route's leg between two meeting areas
// searches it), with the landmarks' bound or
// (`landmarks` false) the octile distance alone; +inf when b is not
// reached. Both bounds are admissible, so both give the least cost; the
// landmarks pop fewer cells. `popped` (optional): adds the cells popped.
double leg_search_cost(const PlanContext& ctx, Point2 a, Point2 b, bool landmarks, std::size_t* popped = nullptr);

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
