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
// max_passes passes. A move stuck at local cuts of a segment searches at
// most max_cut_searches of them for a cut it can take with the small pocket
// behind it (PartitionParams::bap_cut_searches). Every segment stays
// 4-connected and non-empty; the cells labelled 0 stay 0. Deterministic.
void rebalance_areas(int workers, LabelImage& labels, double tolerance, int max_passes, int max_cut_searches);

}  // namespace partition
}  // namespace gather
