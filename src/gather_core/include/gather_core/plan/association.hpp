#pragma once
// Association as a decision (seed sec. 3.1): per worker, deliver to its
// collector or to the OC, and collector routes no longer than the request
// period (docs/planner.md, "Association").
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/plan/route_builder.hpp"

namespace gather {
namespace plan {

// The segments collector c serves, ascending.
std::vector<SegmentId> segments_of(const ConfigurationPlan& cfg, CollectorId c);

// The first step of the association (PlannerOptions::drop_out_of_reach),
// taken on the grown groups before any route is built: every segment that
// no route within the request period can reach (twice the straight way
// from the OC to its entry takes longer) goes to the OC. A collector that
// holds one has a route longer than the period, whose balance would move
// it away anyway. Returns how many moved (added to cfg.moved_to_oc).
int drop_out_of_reach(const PlanContext& ctx, ConfigurationPlan& cfg);

// Balances the routes and moves workers to the OC while that raises the
// score J (see association.cpp); rebuilds the routes it changes (with `fm`,
// a march workspace on the route speed map, and the legs in `legs`) and
// cfg.estimates.
void associate(const PlanContext& ctx, fmm::FastMarching& fm, LegCache& legs, ConfigurationPlan& cfg,
               const PlannerOptions& opt);

}  // namespace plan
}  // namespace gather
