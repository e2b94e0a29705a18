#pragma once
// Figures of the deployment planner, after the seed's Fig. 2 and Fig. 3.
#include <string>
#include <vector>

#include "gather_core/plan/planner.hpp"

namespace gather {
namespace figures {

// DIR/fig2_graph.png (worker graph: segments, centroids, adjacency),
// DIR/fig2_collector_segments.png (the collector groups S_col, direct-to-OC
// segments apart) and DIR/fig2_associations.png (routes, meeting areas and
// which worker delivers to whom, P_cw). Throws gather::Error naming a file
// that cannot be written.
void write_plan_figures(const std::string& dir, const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg);

// Fig. 3 (E curves): estimated refresh time, delivered goals and utility
// against N_c, one curve per method, side by side.
void write_estimates_figure(const std::string& path, const plan::SweepResult& sweep,
                            const std::vector<std::string>& methods);

}  // namespace figures
}  // namespace gather
