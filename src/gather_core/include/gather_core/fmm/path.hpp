#pragma once
// Paths and distances on the arrival times of a FastMarching solve.
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"

namespace gather {
namespace fmm {

struct PathOptions {
  double step = 0.25;  // gradient step [cells]
};

// Bilinear interpolation of the last solve's times [s] at a map-frame point [m],
// over the reached cell centres around it (unreached ones are left out and the
// weights renormalised). kUnreached when none of the four is reached.
double interpolated_time(const FastMarching& fm, Point2 p);

// Gradient descent on the last solve's times from `from` [m] back to the
// source whose front reached it: map-frame points [m], first `from`, last the
// source point (the cell centre for a cell source). Steps of `step` cells
// against the interpolated upwind gradient; where that would enter an
// obstacle, cut an obstacle corner or fail to descend, one step to the centre
// of the lowest neighbouring cell instead. Every point lies in a traversable
// cell, consecutive points are in the same or adjacent cells (never across an
// obstacle corner) and interpolated_time() decreases along the path.
// Throws gather::Error if `from` is off the map, in an obstacle or unreached.
std::vector<Point2> descend(const FastMarching& fm, Point2 from, const PathOptions& options = {});

// Sum of segment lengths [m].
double path_length(const std::vector<Point2>& path);

// Cumulative arc length [m] at each point of a polyline (0 at the first).
std::vector<double> path_arcs(const std::vector<Point2>& path);
// Point at arc length s [m] along a polyline whose cumulative arcs are
// `arcs` (from path_arcs); clamped to its ends; {} for an empty polyline.
Point2 point_at_arc(const std::vector<Point2>& path, const std::vector<double>& arcs, double s);

// point_at_arc for arc positions that mostly grow (sampling a route): the
// same points, found by walking on from the last one instead of a search.
class ArcWalker {
 public:
  ArcWalker(const std::vector<Point2>& path, const std::vector<double>& arcs) : path_(path), arcs_(arcs) {}
  Point2 at(double s);

 private:
  const std::vector<Point2>& path_;
  const std::vector<double>& arcs_;
  std::size_t next_ = 0;  // the first arc > the last s
};

// Geodesic travel time [s] (meters at unit speed) from `a` to `b` [m] at the
// workspace's speed: one march from `a` that stops once `b` is reached.
// kUnreached when no traversable path joins them. Overwrites fm's results.
// Throws gather::Error if `a` is off the map or in an obstacle.
double geodesic_time(FastMarching& fm, Point2 a, Point2 b, Order order = Order::kSecond);

}  // namespace fmm
}  // namespace gather
