#include "gather_core/partition/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_image.hpp"
#include "gather_core/partition/front_growth.hpp"

namespace gather {
namespace partition {

PartitionMetrics compute_metrics(const OccupancyGrid& grid, const PartitionResult& part) {
  PartitionMetrics m;
  const int nw = part.workers;
  m.segments = nw;
  m.runtime_ms = part.runtime_ms;
  const std::size_t n = grid.size();
  std::vector<double> cnt(nw, 0.0), sx(nw, 0.0), sy(nw, 0.0);
  Mask region(grid.frame());
  for (std::size_t i = 0; i < n; ++i) {
    const int32_t l = part.labels[i];
    if (l <= 0) continue;
    region[i] = 1;
    cnt[l - 1] += 1.0;
    const std::size_t col = i % grid.width(), row = i / grid.width();
    sx[l - 1] += static_cast<double>(col);
    sy[l - 1] += static_cast<double>(row);
  }
  m.areas.resize(nw);
  double sum = 0.0, lo = 1e300, hi = 0.0;
  for (int k = 0; k < nw; ++k) {
    m.areas[k] = cnt[k] * grid.cell_area();
    sum += m.areas[k];
    lo = std::min(lo, m.areas[k]);
    hi = std::max(hi, m.areas[k]);
  }
  m.area_mean = sum / nw;
  double var = 0.0;
  for (double a : m.areas) var += (a - m.area_mean) * (a - m.area_mean);
  m.area_cv = m.area_mean > 0.0 ? std::sqrt(var / nw) / m.area_mean : 0.0;
  m.area_ratio = lo > 0.0 ? hi / lo : 0.0;

  // Geodesic radius: fronts confined to their own segment, from the cell
  // nearest each segment's centre of mass.
  std::vector<double> best(nw, 1e300);
  std::vector<FrontGrowth::Front> fronts(nw, FrontGrowth::Front{0, 0.0});
  for (std::size_t i = 0; i < n; ++i) {
    const int32_t l = part.labels[i];
    if (l <= 0) continue;
    const std::size_t col = i % grid.width(), row = i / grid.width();
    const double dx = static_cast<double>(col) - sx[l - 1] / cnt[l - 1];
    const double dy = static_cast<double>(row) - sy[l - 1] / cnt[l - 1];
    if (dx * dx + dy * dy < best[l - 1]) best[l - 1] = dx * dx + dy * dy, fronts[l - 1].cell = i;
  }
  FrontGrowth growth(region);
  std::vector<int32_t> labels;
  std::vector<float> times;
  growth.grow(fronts, labels, &times, &part.labels.values());
  std::vector<double> radius(nw, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (labels[i] > 0 && std::isfinite(times[i]))
      radius[labels[i] - 1] = std::max<double>(radius[labels[i] - 1], times[i]);
  m.compactness.resize(nw);
  double csum = 0.0, cmin = 1e300;
  for (int k = 0; k < nw; ++k) {
    const double disc = std::sqrt(m.areas[k] / 3.14159265358979323846);
    const double r = std::max(radius[k], 0.5 * grid.resolution());
    m.compactness[k] = std::min(1.0, disc / r);
    csum += m.compactness[k];
    cmin = std::min(cmin, m.compactness[k]);
  }
  m.compactness_mean = csum / nw;
  m.compactness_min = cmin;
  return m;
}

LabelImage load_gt_rooms(const std::string& gt_png, const OccupancyGrid& grid, int* rooms, int min_cells) {
  const MapImage img = read_map_image(gt_png);
  if (img.palette_indices && !img.palette_is_gray_ramp)
    throw Error(gt_png, "a palette PNG is not supported as ground truth; save it as RGB");
  if (img.width != grid.width() || img.height != grid.height())
    throw Error(gt_png, "ground truth is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                            ", the map is " + std::to_string(grid.width()) + "x" + std::to_string(grid.height()));
  const std::size_t n = grid.size();
  const int w = grid.width(), h = grid.height();
  // Colour channels: gray (1, or 2 with alpha) or RGB (3, or 4 with alpha); alpha is ignored.
  const int colours = img.channels >= 3 ? 3 : 1;
  std::vector<uint8_t> white(n, 0);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const uint8_t* px = &img.pixels[(static_cast<std::size_t>(r) * w + c) * img.channels];
      bool all = true;
      for (int k = 0; k < colours; ++k) all = all && px[k] >= 250;
      white[static_cast<std::size_t>(h - 1 - r) * w + c] = all;
    }
  std::vector<int32_t> comp(n, 0);
  LabelImage out(grid.frame());
  std::vector<std::size_t> stack, members;
  int32_t id = 0, kept = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (!white[s] || comp[s]) continue;
    comp[s] = ++id;
    stack.assign(1, s);
    members.clear();
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      members.push_back(i);
      const std::size_t col = i % w;
      const std::size_t nb[4] = {col > 0 ? i - 1 : n, col + 1 < static_cast<std::size_t>(w) ? i + 1 : n,
                                 i >= static_cast<std::size_t>(w) ? i - w : n, i + w < n ? i + w : n};
      for (std::size_t j : nb)
        if (j < n && white[j] && !comp[j]) comp[j] = id, stack.push_back(j);
    }
    if (members.size() < static_cast<std::size_t>(min_cells)) continue;
    ++kept;
    for (std::size_t i : members) out[i] = kept;
  }
  if (rooms) *rooms = kept;
  return out;
}

RoomAgreement room_agreement(const LabelImage& labels, const LabelImage& rooms) {
  if (!labels.frame().same_size(rooms.frame()) || !labels.filled() || !rooms.filled())
    throw Error("partition", "room agreement: the label image is " + labels.frame().size_text() + ", the rooms " +
                                 rooms.frame().size_text());
  std::map<std::pair<int32_t, int32_t>, double> overlap;  // (room, segment) -> cells
  std::map<int32_t, double> room_size, seg_size;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] <= 0 || rooms[i] <= 0) continue;
    overlap[{rooms[i], labels[i]}] += 1.0;
    room_size[rooms[i]] += 1.0;
    seg_size[labels[i]] += 1.0;
  }
  std::map<int32_t, double> room_best, seg_best;
  for (const auto& [key, v] : overlap) {
    room_best[key.first] = std::max(room_best[key.first], v);
    seg_best[key.second] = std::max(seg_best[key.second], v);
  }
  RoomAgreement a;
  a.rooms = static_cast<int>(room_size.size());
  double covered = 0.0, total = 0.0;
  for (const auto& [r, v] : room_best) covered += v, total += room_size[r];
  a.recall = total > 0.0 ? covered / total : 0.0;
  double inside = 0.0, seg_total = 0.0;
  for (const auto& [s, v] : seg_best) inside += v, seg_total += seg_size[s];
  a.precision = seg_total > 0.0 ? inside / seg_total : 0.0;
  a.f1 = a.precision + a.recall > 0.0 ? 2.0 * a.precision * a.recall / (a.precision + a.recall) : 0.0;
  return a;
}

}  // namespace partition
}  // namespace gather
