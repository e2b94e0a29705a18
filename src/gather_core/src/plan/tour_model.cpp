#include "gather_core/plan/tour_model.hpp"

namespace gather {
namespace plan {

TourModel first_trip(const WorkerSegment& seg, TourModel m) {
  m.out = seg.mean_oc_distance;
  m.out_quantiles = seg.oc_quantiles;
  return m;
}

TourModel tour_model(const WorkerSegment& seg, bool from_coverage, double c) {
  TourModel m;
  m.area = seg.area;
  m.side = seg.mean_pair_distance > 0 ? seg.mean_pair_distance / kSquarePairDistance : std::sqrt(seg.area);
  m.c = c;
  const double approach = seg.touches_coverage ? 0.0 : seg.coverage_distance;
  if (from_coverage) {
    m.out = seg.mean_home_distance;
    m.out_quantiles = seg.home_quantiles;
    m.back = seg.mean_coverage_distance;
  } else {
    m.out = m.back = std::max(0.0, seg.mean_coverage_distance - approach);
  }
  return m;
}

}  // namespace plan
}  // namespace gather
