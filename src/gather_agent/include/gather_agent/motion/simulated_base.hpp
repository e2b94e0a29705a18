#pragma once
// Simulated kinematics of a worker: each leg follows a shortest path on the
// map (one straight segment when the line of sight is free; otherwise an
// 8-connected A* path, straightened wherever the straight line stays in
// free space) and is driven at the constant pace that reaches its end at
// the planned time (the plan's times are FMM lengths / team speed, so the
// pace is the team speed up to the discretisations). It never fails, is
// never blocked and never late: the ideal base of the analytic equivalence.
#include <vector>

#include "gather_agent/motion/motion_backend.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/path/grid_astar.hpp"

namespace gather {
namespace agent {

// The simulated base's own path choice (what a robot's local planner
// decides, not the protocol): a leg whose way via the home region comes out
// longer than `detour` times the planned length is searched by A* instead,
// range [1, 10].
struct SimulatedBaseParams {
  double detour = 1.2;
};

class SimulatedBase : public MotionBackend {
 public:
  // `paths`: an A* workspace on the grid the plan runs on (it may be shared
  // by the bases of one process; it is only used inside go()). Room for
  // `max_legs` legs a plan; paths are kept in buffers that grow only past
  // their high-water mark.
  // `home`, `home_mask` (optional): a region the base often drives out of
  // and back into (the OC's coverage: mission::World::coverage and
  // coverage_field, a unit-speed march from the region's border cells). A
  // leg back to a border cell walks down that field; a leg from inside the
  // region out to a point leaves it where the point is nearest to it, the
  // way the point would come back (reversed): both without a search across
  // the map.
  // `speed` [m/s]: the team speed the plan's times assume. Throws
  // gather::Error naming the field when `params` are out of range.
  SimulatedBase(const OccupancyGrid& grid, GridAStar& paths, Point2 start, std::size_t max_legs, double speed,
                const fmm::FastMarching* home = nullptr, const Mask* home_mask = nullptr,
                const SimulatedBaseParams& params = {});

  void go(const Waypoint* legs, std::size_t n, double depart) override;
  void stop(double now) override;
  void update(double now) override;
  Point2 pose() const override { return pose_; }
  double heading() const override { return heading_; }
  double speed() const override { return speed_now_; }
  NavState state() const override {
    return n_ == 0 ? NavState::kIdle : done_ < n_ ? NavState::kActive : NavState::kReached;
  }
  std::size_t legs_done() const override { return done_; }
  // Ideal: every waypoint at its planned time.
  double arrived_at(std::size_t leg) const override { return legs_[leg].arrive; }
  double arrival_estimate() const override { return n_ > 0 ? legs_[n_ - 1].arrive : kNoEstimate; }
  std::size_t max_legs() const override { return max_legs_; }
  uint32_t path_revision() const override { return revision_; }
  std::size_t path(Point2* out, std::size_t max) const override;

  // The current plan's path from `leg`'s start to its end [m] (for views).
  std::size_t path_points(std::size_t leg) const { return spans_[leg].second - spans_[leg].first; }
  Point2 path_point(std::size_t leg, std::size_t i) const { return points_[spans_[leg].first + i]; }

 private:
  bool line_of_sight(Point2 a, Point2 b) const;
  Cell descend(Cell from, std::vector<Cell>& out) const;
  bool home_path(Cell a, Cell b);  // into cells_ by the home field; false when it does not apply
  // Appends the leg's polyline to points_; `search`: A* even where the home region would do.
  void plan_path(Point2 from, Point2 to, bool search);

  const OccupancyGrid& grid_;
  double speed_;
  double detour_;
  GridAStar& paths_;
  const fmm::FastMarching* home_;
  const Mask* home_mask_;
  std::size_t max_legs_;
  Point2 pose_;
  double heading_ = 0.0;    // [rad] of the segment it drives (or drove last)
  double speed_now_ = 0.0;  // [m/s]
  double now_ = 0.0;
  std::vector<Waypoint> legs_;
  std::size_t n_ = 0, done_ = 0;
  uint32_t revision_ = 0;
  double depart_ = 0.0;
  std::vector<Point2> points_;                              // every leg's polyline, one after the other
  std::vector<std::pair<std::size_t, std::size_t>> spans_;  // [first, last) in points_ per leg
  std::vector<double> lengths_;                             // [m] per leg
  std::vector<Cell> cells_, tail_;                          // scratch: a path of cells
};

}  // namespace agent
}  // namespace gather
