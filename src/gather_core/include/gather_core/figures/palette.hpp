#pragma once
// The colours of gather's pictures, shared by the PNG figures and the RViz
// markers of gather_oc, so a segment or a collector looks the same in both.
// No OpenCV: plain RGB.
#include <cstdint>
#include <vector>

#include "gather_core/grid/raster.hpp"
#include "gather_core/segment_id.hpp"

namespace gather {
namespace figures {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

// Well-separated fill colours for segments, light enough for dark marks on
// top; no red (the OC). colour_segments() picks among them so that
// neighbours differ.
const std::vector<Rgb>& segment_palette();
// Strong colours for collectors (routes, their workers), distinct from each
// other; no black or grey (grey stands for "delivers to the OC").
const std::vector<Rgb>& collector_palette();

// Colour index per segment such that segments that
// share an edge get different colours when `palette` colours suffice (greedy
// colouring, most-connected segments first).
PerSegment<int> colour_segments(const LabelImage& labels, int segments, int palette);

}  // namespace figures
}  // namespace gather
