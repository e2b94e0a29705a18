#include "plot.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace gather {
namespace figures {
namespace {

// "Nice" tick step for a range, from 1-2-5 x 10^k.
double tick_step(double span, int target) {
  const double raw = span / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) return m * mag;
  return 10 * mag;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return b;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double font = 0.42, int align = 0) {
  int base = 0;
  const cv::Size ts = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, font, 1, &base);
  if (align == 1) at.x -= ts.width / 2;
  if (align == 2) at.x -= ts.width;
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

void marker(cv::Mat& img, cv::Point p, int kind, const cv::Scalar& c) {
  if (kind == 1) {
    cv::rectangle(img, p - cv::Point(4, 4), p + cv::Point(4, 4), c, cv::FILLED);
  } else if (kind == 2) {
    std::vector<cv::Point> tri{p + cv::Point(0, -5), p + cv::Point(5, 4), p + cv::Point(-5, 4)};
    cv::fillConvexPoly(img, tri, c, cv::LINE_AA);
  } else {
    cv::circle(img, p, 4, c, cv::FILLED, cv::LINE_AA);
  }
}

}  // namespace

cv::Mat line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                   const std::vector<Series>& series, cv::Size size) {
  cv::Mat img(size, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const Series& s : series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
      if (!s.band_lo.empty()) y0 = std::min(y0, s.band_lo[i]), y1 = std::max(y1, s.band_hi[i]);
    }
  }
  if (!(x1 >= x0)) x0 = 0, x1 = 1;
  if (!(y1 >= y0)) y0 = 0, y1 = 1;
  if (x1 - x0 < 1e-9) x0 -= 0.5, x1 += 0.5;
  if (y1 - y0 < 1e-9 * std::max(1.0, std::abs(y1)))
    y0 -= std::max(0.5, std::abs(y0) * 0.05), y1 += std::max(0.5, std::abs(y1) * 0.05);
  const double ystep = tick_step(y1 - y0, 5);
  y0 = std::floor(y0 / ystep) * ystep, y1 = std::ceil(y1 / ystep) * ystep;
  const double xstep = std::max(1.0, tick_step(x1 - x0, 8));

  const int left = 62, right = 14, top = 30, legend_h = 18 * static_cast<int>((series.size() + 2) / 3),
            bottom = 44 + legend_h;
  const cv::Rect plot(left, top, size.width - left - right, size.height - top - bottom);
  auto X = [&](double x) { return plot.x + static_cast<int>(std::lround((x - x0) / (x1 - x0) * plot.width)); };
  auto Y = [&](double y) {
    return plot.y + plot.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * plot.height));
  };

  text(img, title, cv::Point(size.width / 2, 19), 0.5, 1);
  for (double y = y0; y <= y1 + 1e-9 * ystep; y += ystep) {
    cv::line(img, cv::Point(plot.x, Y(y)), cv::Point(plot.x + plot.width, Y(y)), cv::Scalar(225, 225, 225), 1);
    text(img, num(y), cv::Point(plot.x - 6, Y(y) + 4), 0.4, 2);
  }
  for (double x = std::ceil(x0 / xstep) * xstep; x <= x1 + 1e-9; x += xstep) {
    cv::line(img, cv::Point(X(x), plot.y + plot.height), cv::Point(X(x), plot.y + plot.height + 4), cv::Scalar(0, 0, 0),
             1);
    text(img, num(x), cv::Point(X(x), plot.y + plot.height + 17), 0.4, 1);
  }
  cv::rectangle(img, plot, cv::Scalar(0, 0, 0), 1);
  text(img, x_label, cv::Point(plot.x + plot.width / 2, plot.y + plot.height + 34), 0.45, 1);
  // Vertical y label, drawn horizontally and rotated.
  {
    int base = 0;
    const cv::Size ts = cv::getTextSize(y_label, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &base);
    cv::Mat lab(ts.height + 8, ts.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::putText(lab, y_label, cv::Point(2, ts.height + 2), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    cv::Mat rot;
    cv::rotate(lab, rot, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int ry = std::max(0, plot.y + plot.height / 2 - rot.rows / 2);
    if (ry + rot.rows <= img.rows && rot.cols + 4 <= left) rot.copyTo(img(cv::Rect(4, ry, rot.cols, rot.rows)));
  }
  // Bands first (translucent), then lines and markers.
  for (const Series& s : series) {
    if (s.band_lo.empty() || s.x.size() < 2) continue;
    std::vector<cv::Point> poly;
    for (std::size_t i = 0; i < s.x.size(); ++i) poly.emplace_back(X(s.x[i]), Y(s.band_hi[i]));
    for (std::size_t i = s.x.size(); i-- > 0;) poly.emplace_back(X(s.x[i]), Y(s.band_lo[i]));
    cv::Mat overlay = img.clone();
    cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{poly}, s.colour, cv::LINE_AA);
    cv::addWeighted(overlay, 0.22, img, 0.78, 0, img);
  }
  for (const Series& s : series) {
    for (std::size_t i = 1; i < s.x.size(); ++i) {
      const cv::Point a(X(s.x[i - 1]), Y(s.y[i - 1])), b(X(s.x[i]), Y(s.y[i]));
      if (!s.dashed) {
        cv::line(img, a, b, s.colour, 2, cv::LINE_AA);
      } else {
        const double len = std::hypot(b.x - a.x, b.y - a.y);
        for (double t = 0; t < len; t += 9.0)
          cv::line(img, a + (b - a) * (t / len), a + (b - a) * (std::min(len, t + 5.0) / len), s.colour, 2,
                   cv::LINE_AA);
      }
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) marker(img, cv::Point(X(s.x[i]), Y(s.y[i])), s.marker, s.colour);
  }
  // Legend below the x label, three entries per row.
  const int col_w = (size.width - 20) / 3;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const int lx = 10 + static_cast<int>(i % 3) * col_w, ly = plot.y + plot.height + 52 + static_cast<int>(i / 3) * 18;
    cv::line(img, cv::Point(lx, ly - 4), cv::Point(lx + 22, ly - 4), series[i].colour, 2, cv::LINE_AA);
    marker(img, cv::Point(lx + 11, ly - 4), series[i].marker, series[i].colour);
    text(img, series[i].name, cv::Point(lx + 28, ly), 0.4);
  }
  return img;
}

}  // namespace figures
}  // namespace gather
