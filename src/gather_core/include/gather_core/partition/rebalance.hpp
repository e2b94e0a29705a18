#pragma once
// Area rebalancing of a partition (BAP's last step): boundary cells move
// between adjacent segments until their areas agree.
#include "gather_core/grid/raster.hpp"

namespace gather {
namespace partition {

// Moves boundary cells between adjacent segments of `labels` (0 = no
// segment, segments 1..workers each 4-connected) until
// every segment's area is within tolerance * mean of the mean (tolerance: a
// fraction, dimensionless), or after
// max_passes passes. Every segment stays 4-connected and non-empty; the
// cells labelled 0 stay 0. Deterministic.
void rebalance_areas(int workers, LabelImage& labels, double tolerance, int max_passes);

}  // namespace partition
}  // namespace gather
