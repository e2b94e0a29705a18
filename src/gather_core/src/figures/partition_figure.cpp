#include "gather_core/figures/partition_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "gather_core/error.hpp"
#include "map_canvas.hpp"

namespace gather {
namespace figures {
namespace {

using partition::PartitionResult;

const cv::Vec3b kObstacle{45, 45, 45}, kUnknown{150, 150, 150}, kUnreachable{215, 215, 215};

// Pixel scale of a panel: small maps are enlarged, very large ones reduced.
double panel_scale(const OccupancyGrid& g) {
  const int big = std::max(g.width(), g.height());
  if (big < 500) return 2.0;
  if (big > 1600) return 1600.0 / big;
  return 1.0;
}

// Background: obstacles, unknown and unreachable cells (image orientation).
cv::Mat base_image(const OccupancyGrid& g) {
  cv::Mat img(g.height(), g.width(), CV_8UC3);
  for (int r = 0; r < g.height(); ++r)
    for (int c = 0; c < g.width(); ++c) {
      const Cell cell{g.height() - 1 - r, c};
      img.at<cv::Vec3b>(r, c) = g.is_free(cell) ? kUnreachable : (g.value(cell) < 0 ? kUnknown : kObstacle);
    }
  return img;
}

cv::Point to_pixel(const OccupancyGrid& g, Cell c, double s) {
  return cv::Point(static_cast<int>((c.col + 0.5) * s), static_cast<int>((g.height() - 1 - c.row + 0.5) * s));
}

void draw_marks(cv::Mat& img, const OccupancyGrid& g, const std::vector<Cell>& seeds, Point2 oc, double s,
                bool numbers) {
  const int rad = std::max(3, static_cast<int>(std::lround(0.25 / g.resolution() * s)));
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    const cv::Point p = to_pixel(g, seeds[k], s);
    cv::circle(img, p, rad, cv::Scalar(255, 255, 255), cv::FILLED, cv::LINE_AA);
    cv::circle(img, p, rad, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    if (numbers) {
      cv::putText(img, std::to_string(k + 1), p + cv::Point(rad + 1, -rad), cv::FONT_HERSHEY_SIMPLEX, 0.38,
                  cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
  }
  const cv::Point o = to_pixel(g, g.world_to_cell(oc), s);
  const int half = std::max(5, static_cast<int>(std::lround(0.35 / g.resolution() * s)));
  cv::rectangle(img, o - cv::Point(half, half), o + cv::Point(half, half), cv::Scalar(0, 0, 230), cv::FILLED);
  cv::rectangle(img, o - cv::Point(half, half), o + cv::Point(half, half), cv::Scalar(0, 0, 0), 1);
}

// Caption strip above, scale bar and legend strip below.
cv::Mat frame(const cv::Mat& map, const OccupancyGrid& g, double s, const std::string& caption) {
  const int top = 26, bottom = 28;
  cv::Mat out(map.rows + top + bottom, std::max(map.cols, 360), CV_8UC3, cv::Scalar(255, 255, 255));
  map.copyTo(out(cv::Rect(0, top, map.cols, map.rows)));
  cv::putText(out, caption, cv::Point(6, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Scale bar: the 1-2-5 length nearest a fifth of the map width.
  const double width_m = g.width() * g.resolution();
  double len = 1.0;
  for (double cand : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0})
    if (cand <= width_m / 5.0) len = cand;
  const int px = static_cast<int>(std::lround(len / g.resolution() * s));
  const int y = map.rows + top + 14;
  cv::rectangle(out, cv::Point(8, y - 4), cv::Point(8 + px, y + 2), cv::Scalar(0, 0, 0), cv::FILLED);
  char text[64];
  std::snprintf(text, sizeof(text), "%g m", len);
  cv::putText(out, text, cv::Point(14 + px, y + 3), cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  const int lx = 70 + px;
  cv::rectangle(out, cv::Point(lx, y - 5), cv::Point(lx + 9, y + 4), cv::Scalar(0, 0, 230), cv::FILLED);
  cv::putText(out, "OC", cv::Point(lx + 13, y + 3), cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  cv::circle(out, cv::Point(lx + 50, y), 4, cv::Scalar(255, 255, 255), cv::FILLED, cv::LINE_AA);
  cv::circle(out, cv::Point(lx + 50, y), 4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(out, "seed", cv::Point(lx + 58, y + 3), cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  return out;
}

cv::Mat scaled(const cv::Mat& img, double s) {
  if (s == 1.0) return img;
  cv::Mat out;
  cv::resize(img, out, cv::Size(), s, s, s > 1.0 ? cv::INTER_NEAREST : cv::INTER_AREA);
  return out;
}

cv::Mat partition_panel(const OccupancyGrid& g, const PartitionResult& part, Point2 oc, const std::string& caption) {
  require_same_size(part.labels, g.frame(), "partition figure", "the label image");
  require_same_size(part.clearance, g.frame(), "partition figure", "the clearance");
  const int w = g.width(), h = g.height();
  const PerSegment<int> colour = colour_segments(part.labels, part.workers, static_cast<int>(fill_palette().size()));
  cv::Mat img = base_image(g);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(h - 1 - r) * w + c;
      const int32_t l = part.labels[i];
      if (l <= 0) continue;
      cv::Vec3b col = fill_palette()[static_cast<std::size_t>(colour[SegmentId(l)])];
      // Segment borders (a 4-neighbour in another segment) drawn dark.
      const bool border = (c + 1 < w && part.labels[i + 1] > 0 && part.labels[i + 1] != l) ||
                          (c > 0 && part.labels[i - 1] > 0 && part.labels[i - 1] != l) ||
                          (i + w < part.labels.size() && part.labels[i + w] > 0 && part.labels[i + w] != l) ||
                          (i >= static_cast<std::size_t>(w) && part.labels[i - w] > 0 && part.labels[i - w] != l);
      if (border) col = cv::Vec3b(col[0] / 3, col[1] / 3, col[2] / 3);
      img.at<cv::Vec3b>(r, c) = col;
    }
  const double s = panel_scale(g);
  cv::Mat big = scaled(img, s);
  draw_marks(big, g, part.seeds, oc, s, part.workers <= 40);
  return frame(big, g, s, caption);
}

cv::Mat seeds_panel(const OccupancyGrid& g, const PartitionResult& part, Point2 oc, const std::string& caption) {
  const int w = g.width(), h = g.height();
  cv::Mat img = base_image(g);
  float max_clr = 1e-6f;
  for (std::size_t i = 0; i < part.labels.size(); ++i)
    if (part.labels[i] > 0) max_clr = std::max(max_clr, part.clearance[i]);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(h - 1 - r) * w + c;
      if (part.labels[i] <= 0) continue;
      const double t = std::sqrt(part.clearance[i] / max_clr);  // 0 at walls, 1 at the widest spot
      img.at<cv::Vec3b>(r, c) = cv::Vec3b(static_cast<uint8_t>(255 - 40 * t), static_cast<uint8_t>(245 - 120 * t),
                                          static_cast<uint8_t>(235 - 200 * t));
    }
  const double s = panel_scale(g);
  cv::Mat big = scaled(img, s);
  draw_marks(big, g, part.initial_seeds, oc, s, part.workers <= 40);
  return frame(big, g, s, caption);
}

cv::Mat pad_to(const cv::Mat& img, int w, int h) {
  cv::Mat out(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  img.copyTo(out(cv::Rect(0, 0, img.cols, img.rows)));
  return out;
}

}  // namespace

void write_partition_png(const std::string& path, const OccupancyGrid& grid, const PartitionResult& part, Point2 oc,
                         const std::string& caption) {
  write_png(path, partition_panel(grid, part, oc, caption));
}

void write_seeds_png(const std::string& path, const OccupancyGrid& grid, const PartitionResult& part, Point2 oc,
                     const std::string& caption) {
  write_png(path, seeds_panel(grid, part, oc, caption));
}

void write_compare_png(const std::string& path, const OccupancyGrid& grid, const std::vector<PartitionResult>& parts,
                       const std::vector<std::string>& captions, Point2 oc) {
  std::vector<cv::Mat> panels;
  const PartitionResult* with_seeds = nullptr;
  for (const auto& p : parts)
    if (!p.initial_seeds.empty() && (!with_seeds || p.method == partition::Method::kPap)) with_seeds = &p;
  const char* letters = "abcdefgh";
  std::size_t letter = 0;
  auto caption_of = [&](std::size_t k) { return k < captions.size() ? captions[k] : std::string(); };
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].method != partition::Method::kBap) continue;
    panels.push_back(partition_panel(grid, parts[k], oc, std::string("(") + letters[letter++] + ") " + caption_of(k)));
  }
  if (with_seeds)
    panels.push_back(seeds_panel(grid, *with_seeds, oc,
                                 std::string("(") + letters[letter++] + ") centroid initialisation for PAP/RAP"));
  for (partition::Method m : {partition::Method::kPap, partition::Method::kRap})
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (parts[k].method == m)
        panels.push_back(
            partition_panel(grid, parts[k], oc, std::string("(") + letters[letter++] + ") " + caption_of(k)));
  if (panels.empty()) throw Error(path, "nothing to draw");
  int pw = 0, ph = 0;
  for (const auto& p : panels) pw = std::max(pw, p.cols), ph = std::max(ph, p.rows);
  for (auto& p : panels) p = pad_to(p, pw + 8, ph + 8);
  const bool grid2 = grid.width() >= grid.height() && panels.size() == 4;
  cv::Mat out;
  if (grid2) {
    cv::Mat top, bottom;
    cv::hconcat(panels[0], panels[1], top);
    cv::hconcat(panels[2], panels[3], bottom);
    cv::vconcat(top, bottom, out);
  } else {
    cv::hconcat(panels, out);
  }
  write_png(path, out);
}

}  // namespace figures
}  // namespace gather
