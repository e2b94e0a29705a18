#pragma once
// Line charts with axes, ticks, a legend and optional min-max bands (for the
// estimated E curves and real R bands of Fig. 3). Internal to gather_core.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace gather {
namespace figures {

struct Series {
  std::string name;
  cv::Scalar colour;
  std::vector<double> x, y;
  std::vector<double> band_lo, band_hi;  // empty, or one per x: a shaded min-max band
  bool dashed = false;
  int marker = 0;  // 0 circle, 1 square, 2 triangle
};

// A chart of `size` pixels; y range from the data (bands included), padded.
cv::Mat line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                   const std::vector<Series>& series, cv::Size size);

}  // namespace figures
}  // namespace gather
