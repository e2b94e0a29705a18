#pragma once
// Drawing a map figure with OpenCV (internal to gather_core's figures): cells
// painted at map resolution, then scaled; marks and lines on the scaled
// image; a caption above and a scale bar and legend below.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace figures {

// Well-separated fill colours (BGR), light enough for dark marks on top; no red (the OC).
const std::vector<cv::Vec3b>& fill_palette();
// Strong line/marker colours (BGR) for routes and groups, distinct from each other.
const std::vector<cv::Scalar>& line_palette();

struct LegendItem {
  enum Kind { kSquare, kCircle, kLine } kind;
  cv::Scalar colour;
  std::string text;
};

class MapCanvas {
 public:
  // Obstacles dark, unknown grey, free cells `free_colour`.
  explicit MapCanvas(const OccupancyGrid& grid, const cv::Vec3b& free_colour = cv::Vec3b(235, 235, 235));

  // Cell colours at map resolution (call before the first mark).
  void paint(Cell c, const cv::Vec3b& colour);
  // Scaled image with marks; the first call freezes the painted cells.
  cv::Mat& image();
  const OccupancyGrid& grid() const { return grid_; }  // the map drawn
  double scale() const { return scale_; }              // [px per cell]
  cv::Point px(Point2 p) const;                        // map point [m] -> pixel
  cv::Point px(Cell c) const;
  int px_len(double meters) const;  // a length [m] in pixels

  void oc(Point2 p);                                          // red square
  void dot(Point2 p, const cv::Scalar& fill, int radius_px);  // black-edged disc
  void polyline(const std::vector<Point2>& pts, const cv::Scalar& colour, int thickness, bool dashed = false);
  void label(Point2 p, const std::string& text, double font = 0.4);

  // Caption above, scale bar and legend below; writes the PNG. Throws
  // gather::Error naming the file when it cannot be written.
  void save(const std::string& path, const std::string& caption, const std::vector<LegendItem>& legend);
  // The framed figure without writing it (for side-by-side panels).
  cv::Mat framed(const std::string& caption, const std::vector<LegendItem>& legend);

 private:
  const OccupancyGrid& grid_;
  double scale_;
  cv::Mat cells_;
  cv::Mat img_;
};

void write_png(const std::string& path, const cv::Mat& img);

}  // namespace figures
}  // namespace gather
