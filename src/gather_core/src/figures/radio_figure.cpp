#include "gather_core/figures/radio_figure.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "map_canvas.hpp"

namespace gather {
namespace figures {

void write_coverage_png(const std::string& path, const OccupancyGrid& g, const RadioModel& radio, Point2 tx,
                        const Mask& coverage, const std::string& caption) {
  require_same_size(coverage, g.frame(), path, "coverage mask");
  MapCanvas canvas(g, cv::Vec3b(225, 225, 225));
  const double sens = radio.params().sensitivity_dbm;
  const double top = radio.params().tx_power_dbm - radio.params().ref_loss_db;  // received at 1 m
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (!coverage[i]) continue;
    const Cell c = g.cell(i);
    // Strong signal dark green, near the sensitivity pale green.
    const double t =
        std::clamp((radio.received_dbm(tx, g.cell_center(c)) - sens) / std::max(1.0, top - sens), 0.0, 1.0);
    canvas.paint(c, cv::Vec3b(static_cast<uchar>(200 - 140 * t), static_cast<uchar>(240 - 90 * t),
                              static_cast<uchar>(200 - 160 * t)));
  }
  cv::Mat& img = canvas.image();
  const int r = canvas.px_len(radio.free_space_range());
  const cv::Point o = canvas.px(tx);
  for (int a = 0; a < 360; a += 6)
    cv::ellipse(img, o, cv::Size(r, r), 0, a, a + 3, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  canvas.oc(tx);
  canvas.save(path, caption,
              {{LegendItem::kSquare, cv::Scalar(60, 150, 40), "linked, strong"},
               {LegendItem::kSquare, cv::Scalar(200, 240, 200), "linked, near sensitivity"},
               {LegendItem::kSquare, cv::Scalar(225, 225, 225), "free, no link"},
               {LegendItem::kLine, cv::Scalar(60, 60, 60), "free-space range"},
               {LegendItem::kSquare, cv::Scalar(0, 0, 230), "transmitter"}});
}

}  // namespace figures
}  // namespace gather
