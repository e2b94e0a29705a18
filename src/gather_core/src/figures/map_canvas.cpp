#include "map_canvas.hpp"

#include "gather_core/figures/palette.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_image.hpp"

namespace gather {
namespace figures {

const std::vector<cv::Vec3b>& fill_palette() {
  static const std::vector<cv::Vec3b> p = [] {
    std::vector<cv::Vec3b> out;
    for (const Rgb& c : segment_palette()) out.emplace_back(c.b, c.g, c.r);
    return out;
  }();
  return p;
}

const std::vector<cv::Scalar>& line_palette() {
  static const std::vector<cv::Scalar> p = [] {
    std::vector<cv::Scalar> out;
    for (const Rgb& c : collector_palette()) out.emplace_back(c.b, c.g, c.r);
    return out;
  }();
  return p;
}

void write_png(const std::string& path, const cv::Mat& img) {
  // libpng through gather_core, not OpenCV's imgcodecs: loading that (and
  // the many libraries behind it) took most of a gather command's start.
  if (img.type() != CV_8UC3 || img.empty()) throw Error(path, "cannot write PNG: the figure is not an 8-bit BGR image");
  std::vector<uint8_t> rgb(img.total() * 3);
  for (int r = 0; r < img.rows; ++r) {
    const auto* in = img.ptr<cv::Vec3b>(r);
    uint8_t* out = rgb.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(img.cols) * 3;
    for (int c = 0; c < img.cols; ++c, out += 3) out[0] = in[c][2], out[1] = in[c][1], out[2] = in[c][0];
  }
  write_rgb8_png(path, img.cols, img.rows, rgb.data(), static_cast<std::size_t>(img.cols) * 3);
}

MapCanvas::MapCanvas(const OccupancyGrid& g, const cv::Vec3b& free_colour) : grid_(g) {
  const int big = std::max(g.width(), g.height());
  // Small (or coarse planning) grids are magnified to about 1200 px.
  scale_ = big < 800 ? std::floor(1200.0 / big) : (big > 1600 ? 1600.0 / big : 1.0);
  cells_.create(g.height(), g.width(), CV_8UC3);
  for (int r = 0; r < g.height(); ++r)
    for (int c = 0; c < g.width(); ++c) {
      const Cell cell{g.height() - 1 - r, c};
      cells_.at<cv::Vec3b>(r, c) =
          g.is_free(cell) ? free_colour : (g.value(cell) < 0 ? cv::Vec3b(150, 150, 150) : cv::Vec3b(45, 45, 45));
    }
}

void MapCanvas::paint(Cell c, const cv::Vec3b& colour) {
  cells_.at<cv::Vec3b>(grid_.height() - 1 - c.row, c.col) = colour;
}

cv::Mat& MapCanvas::image() {
  if (img_.empty()) {
    if (scale_ == 1.0)
      img_ = cells_.clone();
    else
      cv::resize(cells_, img_, cv::Size(), scale_, scale_, scale_ > 1.0 ? cv::INTER_NEAREST : cv::INTER_AREA);
  }
  return img_;
}

cv::Point MapCanvas::px(Point2 p) const {
  const double fx = (p.x - grid_.origin().x) / grid_.resolution();
  const double fy = grid_.height() - (p.y - grid_.origin().y) / grid_.resolution();
  return cv::Point(static_cast<int>(std::lround(fx * scale_)), static_cast<int>(std::lround(fy * scale_)));
}

cv::Point MapCanvas::px(Cell c) const { return px(grid_.cell_center(c)); }

int MapCanvas::px_len(double m) const {
  return std::max(1, static_cast<int>(std::lround(m / grid_.resolution() * scale_)));
}

void MapCanvas::oc(Point2 p) {
  const cv::Point o = px(p);
  const int half = std::max(5, px_len(0.4));
  cv::rectangle(image(), o - cv::Point(half, half), o + cv::Point(half, half), cv::Scalar(0, 0, 230), cv::FILLED);
  cv::rectangle(image(), o - cv::Point(half, half), o + cv::Point(half, half), cv::Scalar(0, 0, 0), 1);
}

void MapCanvas::dot(Point2 p, const cv::Scalar& fill, int radius) {
  cv::circle(image(), px(p), radius, fill, cv::FILLED, cv::LINE_AA);
  cv::circle(image(), px(p), radius, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

void MapCanvas::polyline(const std::vector<Point2>& pts, const cv::Scalar& colour, int thickness, bool dashed) {
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const cv::Point a = px(pts[i - 1]), b = px(pts[i]);
    if (!dashed) {
      cv::line(image(), a, b, colour, thickness, cv::LINE_AA);
      continue;
    }
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    for (double t = 0; t < len; t += 10.0) {
      const double t1 = std::min(len, t + 6.0);
      cv::line(image(), a + (b - a) * (t / len), a + (b - a) * (t1 / len), colour, thickness, cv::LINE_AA);
    }
  }
}

void MapCanvas::label(Point2 p, const std::string& text, double font) {
  const cv::Point at = px(p) + cv::Point(5, -5);
  cv::putText(image(), text, at, cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
  cv::putText(image(), text, at, cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

cv::Mat MapCanvas::framed(const std::string& caption, const std::vector<LegendItem>& legend) {
  const cv::Mat& map = image();
  const int top = 28, bottom = 30;
  const int width = std::max(map.cols, 420);
  // Legend items flow left to right after the scale bar, wrapping as needed.
  std::vector<int> item_w;
  for (const auto& it : legend) {
    int base = 0;
    item_w.push_back(22 + cv::getTextSize(it.text, cv::FONT_HERSHEY_SIMPLEX, 0.42, 1, &base).width + 14);
  }
  const double width_m = grid_.width() * grid_.resolution();
  double len = 1.0;
  for (double cand : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0})
    if (cand <= width_m / 5.0) len = cand;
  const int bar = px_len(len);
  int rows = 1, x = 60 + bar;
  for (int w : item_w) {
    if (x + w > width) ++rows, x = 8;
    x += w;
  }
  cv::Mat out(map.rows + top + bottom + (rows - 1) * 20, width, CV_8UC3, cv::Scalar(255, 255, 255));
  map.copyTo(out(cv::Rect(0, top, map.cols, map.rows)));
  cv::putText(out, caption, cv::Point(6, 19), cv::FONT_HERSHEY_SIMPLEX, 0.52, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  int y = map.rows + top + 16;
  cv::rectangle(out, cv::Point(8, y - 4), cv::Point(8 + bar, y + 2), cv::Scalar(0, 0, 0), cv::FILLED);
  char text[32];
  std::snprintf(text, sizeof text, "%g m", len);
  cv::putText(out, text, cv::Point(14 + bar, y + 3), cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  x = 60 + bar;
  for (std::size_t i = 0; i < legend.size(); ++i) {
    if (x + item_w[i] > width) y += 20, x = 8;
    const LegendItem& it = legend[i];
    const cv::Point c(x + 7, y - 1);
    if (it.kind == LegendItem::kSquare) {
      cv::rectangle(out, c - cv::Point(6, 6), c + cv::Point(6, 6), it.colour, cv::FILLED);
      cv::rectangle(out, c - cv::Point(6, 6), c + cv::Point(6, 6), cv::Scalar(0, 0, 0), 1);
    } else if (it.kind == LegendItem::kCircle) {
      cv::circle(out, c, 5, it.colour, cv::FILLED, cv::LINE_AA);
      cv::circle(out, c, 5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    } else {
      cv::line(out, c - cv::Point(8, 0), c + cv::Point(8, 0), it.colour, 3, cv::LINE_AA);
    }
    cv::putText(out, it.text, cv::Point(x + 20, y + 3), cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    x += item_w[i];
  }
  return out;
}

void MapCanvas::save(const std::string& path, const std::string& caption, const std::vector<LegendItem>& legend) {
  write_png(path, framed(caption, legend));
}

}  // namespace figures
}  // namespace gather
