#include "gather_core/figures/palette.hpp"

#include <algorithm>
#include <set>

namespace gather {
namespace figures {

const std::vector<Rgb>& segment_palette() {
  static const std::vector<Rgb> p = {{67, 99, 216},   {60, 180, 75},  {255, 225, 25},  {245, 130, 49},
                                     {145, 30, 180},  {66, 212, 244}, {240, 50, 230},  {191, 239, 69},
                                     {250, 190, 212}, {70, 153, 144}, {220, 190, 255}, {154, 99, 36},
                                     {170, 255, 195}, {128, 128, 0},  {255, 216, 177}, {255, 250, 200}};
  return p;
}

const std::vector<Rgb>& collector_palette() {
  static const std::vector<Rgb> p = {{30, 100, 200}, {240, 130, 20}, {40, 150, 40}, {150, 50, 150}, {150, 80, 40},
                                     {0, 150, 150},  {220, 40, 180}, {140, 140, 0}, {40, 40, 130},  {200, 60, 60}};
  return p;
}

PerSegment<int> colour_segments(const LabelImage& labels, int segments, int palette) {
  const int width = labels.width(), height = labels.height();
  PerSegment<std::set<SegmentId>> adj(segments);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * width + c;
      const SegmentId l(labels[i]);
      if (!l.valid()) continue;
      const SegmentId right(c + 1 < width ? labels[i + 1] : 0);
      const SegmentId up(r + 1 < height ? labels[i + width] : 0);
      for (SegmentId m : {right, up})
        if (m.valid() && m != l) adj[l].insert(m), adj[m].insert(l);
    }
  std::vector<SegmentId> order;
  for (SegmentId k : segment_ids(segments)) order.push_back(k);
  std::stable_sort(order.begin(), order.end(), [&](SegmentId a, SegmentId b) { return adj[a].size() > adj[b].size(); });
  PerSegment<int> colour(segments, -1);
  std::vector<int> used(static_cast<std::size_t>(palette), 0);
  for (SegmentId k : order) {
    std::vector<int> clash(static_cast<std::size_t>(palette), 0);
    for (SegmentId m : adj[k])
      if (colour[m] >= 0) ++clash[static_cast<std::size_t>(colour[m])];
    // Fewest clashes first, then the least used colour (spreads the palette).
    int best = 0;
    for (int c = 1; c < palette; ++c)
      if (clash[c] < clash[best] || (clash[c] == clash[best] && used[c] < used[best])) best = c;
    colour[k] = best;
    ++used[best];
  }
  return colour;
}

}  // namespace figures
}  // namespace gather
