#pragma once
// Each segment's walking distances for the estimate: from its OC worker's
// home, from the OC's cell, and between its cells (docs/planner.md,
// "Estimate model").
#include <cstdint>
#include <vector>

#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// Fills graph.segments' mean_home_distance, home_quantiles,
// mean_oc_distance, oc_quantiles and mean_pair_distance (see
// walking_distances.cpp); returns each cell's rank in its segment by
// walking distance from that home, in [0, 1) (-1 off the segments), in the
// labels' frame.
// `opt`: pair_sources and home_box_margin_m.
Field segment_distances(const PlanContext& ctx, const LabelImage& labels, WorkerGraph& graph,
                        const PlannerOptions& opt);

}  // namespace plan
}  // namespace gather
