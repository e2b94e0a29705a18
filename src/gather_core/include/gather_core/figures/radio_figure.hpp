#pragma once
// Picture of a transmitter's radio coverage.
#include <string>
#include <vector>

#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace figures {

// Free cells linked to `tx` shaded by received power, the others grey; the
// free-space range as a dashed circle; tx as a red square.
void write_coverage_png(const std::string& path, const OccupancyGrid& grid, const RadioModel& radio, Point2 tx,
                        const Mask& coverage, const std::string& caption);

}  // namespace figures
}  // namespace gather
