#include "gather_core/path/path_polisher.hpp"

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <cmath>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"

namespace gather {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// Smallest free_distance along segment a-b, sampled every `step` [m].
double segment_clearance(const ClearanceMap& cm, Point2 a, Point2 b, double step) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
  double worst = cm.free_distance(a);
  for (int i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    const Point2 p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    // A sample that cannot go below the worst so far is not worked out (the same minimum).
    if (cm.free_distance_floor(p) >= worst) continue;
    worst = std::min(worst, cm.free_distance(p));
  }
  return worst;
}

std::vector<Point2> shortcut(const std::vector<Point2>& in, const ClearanceMap& cm, double radius, double step) {
  std::vector<Point2> out{in.front()};
  const std::size_t last = in.size() - 1;
  std::size_t i = 0;
  auto clear = [&](std::size_t a, std::size_t b) { return segment_clearance(cm, in[a], in[b], step) >= radius; };
  while (i < last) {
    // The next point is always reachable (the input's own segment). Gallop
    // ahead while the straight segment stays clear, then bisect between the
    // last clear and the first blocked end: O(log n) checks per kept point.
    std::size_t good = i + 1, span = 1;
    std::size_t bad = last + 1;
    while (good < last) {
      const std::size_t probe = std::min(last, i + 2 * span);
      if (clear(i, probe)) {
        good = probe;
        span *= 2;
      } else {
        bad = probe;
        break;
      }
    }
    while (bad - good > 1) {
      const std::size_t mid = good + (bad - good) / 2;
      if (clear(i, mid))
        good = mid;
      else
        bad = mid;
    }
    out.push_back(in[good]);
    i = good;
  }
  return out;
}

}  // namespace

PolishedPath polish_path(const std::vector<Point2>& path, const ClearanceMap& cm, const PolishOptions& opt) {
  if (path.empty()) throw Error("polish_path", "empty path");
  const OccupancyGrid& g = cm.grid();
  const double step = opt.check_step > 0 ? opt.check_step : 0.5 * g.resolution();
  const double r = opt.robot_radius;
  PolishedPath result;
  result.points = path.size() < 3 ? path : shortcut(path, cm, r, step);

  if (opt.smoothing_passes > 0 && result.points.size() >= 3) {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    auto space = std::make_shared<ob::RealVectorStateSpace>(2);
    ob::RealVectorBounds bounds(2);
    bounds.setLow(0, g.origin().x);
    bounds.setHigh(0, g.origin().x + g.width() * g.resolution());
    bounds.setLow(1, g.origin().y);
    bounds.setHigh(1, g.origin().y + g.height() * g.resolution());
    space->setBounds(bounds);
    auto si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([&cm, r](const ob::State* s) {
      const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
      return cm.disc_free(Point2{v->values[0], v->values[1]}, r);
    });
    si->setStateValidityCheckingResolution(step / space->getMaximumExtent());
    si->setup();
    og::PathGeometric pg(si);
    ob::ScopedState<ob::RealVectorStateSpace> st(space);
    for (const Point2& p : result.points) {
      st[0] = p.x;
      st[1] = p.y;
      pg.append(st.get());
    }
    // B-spline smoothing only replaces a corner when the new motion is valid,
    // so stretches that were clear stay clear.
    og::PathSimplifier simplifier(si);
    simplifier.smoothBSpline(pg, opt.smoothing_passes);
    std::vector<Point2> smoothed;
    for (std::size_t i = 0; i < pg.getStateCount(); ++i) {
      const auto* v = pg.getState(i)->as<ob::RealVectorStateSpace::StateType>();
      smoothed.push_back(Point2{v->values[0], v->values[1]});
    }
    // B-spline smoothing doubles the vertices at each pass: keep one every
    // `min_spacing` metres (chords that short stay within millimetres of the curve).
    if (opt.min_spacing > 0 && smoothed.size() > 2) {
      std::vector<Point2> thin{smoothed.front()};
      for (std::size_t i = 1; i + 1 < smoothed.size(); ++i)
        if (std::hypot(smoothed[i].x - thin.back().x, smoothed[i].y - thin.back().y) >= opt.min_spacing)
          thin.push_back(smoothed[i]);
      thin.push_back(smoothed.back());
      smoothed.swap(thin);
    }
    // Keep the smoothing only if it did not make things worse anywhere.
    double before = 1e300, after = 1e300;
    for (std::size_t i = 1; i < result.points.size(); ++i)
      before = std::min(before, segment_clearance(cm, result.points[i - 1], result.points[i], step));
    for (std::size_t i = 1; i < smoothed.size(); ++i)
      after = std::min(after, segment_clearance(cm, smoothed[i - 1], smoothed[i], step));
    if (after >= std::min(before, r)) result.points = std::move(smoothed);
  }
  result.length = fmm::path_length(result.points);
  result.min_clearance = cm.free_distance(result.points.front());
  for (std::size_t i = 1; i < result.points.size(); ++i)
    result.min_clearance =
        std::min(result.min_clearance, segment_clearance(cm, result.points[i - 1], result.points[i], step));
  return result;
}

}  // namespace gather
