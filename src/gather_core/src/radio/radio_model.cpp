#include "gather_core/radio/radio_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace gather {

RadioModel::RadioModel(const OccupancyGrid& grid, const RadioParams& params) : grid_(grid), params_(params) {
  const double budget = params_.tx_power_dbm - params_.ref_loss_db - params_.sensitivity_dbm;
  free_range_m_ = budget < 0 ? 0.0 : std::pow(10.0, budget / (10.0 * params_.exponent));
}

double RadioModel::received_without_walls(double d_m) const {
  return params_.tx_power_dbm - params_.ref_loss_db - 10.0 * params_.exponent * std::log10(std::max(d_m, 1.0));
}

double RadioModel::received_for(double d_m, int walls) const {
  return received_without_walls(d_m) - params_.wall_loss_db * std::min(walls, params_.max_walls);
}

// Walls a link that receives `clear` [dBm] without walls can afford (same
// arithmetic as received_for), computed, not counted up: max_walls may be huge.
int RadioModel::affordable_walls(double clear) const {
  const double sens = params_.sensitivity_dbm, loss = params_.wall_loss_db;
  const int most = params_.max_walls;
  if (!(loss > 0.0)) return most;
  const double guess = std::floor((clear - sens) / loss);
  int k = guess <= 0 ? 0 : guess >= most ? most : static_cast<int>(guess);
  while (k > 0 && clear - loss * k < sens) --k;
  while (k < most && clear - loss * (k + 1) >= sens) ++k;
  return k;
}

bool RadioModel::linked(Point2 a, Point2 b, double d) const {
  const double clear = received_without_walls(d);
  if (clear < params_.sensitivity_dbm) return false;
  // Counting walls stops one past the affordable ones (a long segment
  // through many walls costs no more than its first few).
  const int affordable = affordable_walls(clear);
  if (affordable >= params_.max_walls) return true;
  const double r = grid_.resolution();
  const Point2 o = grid_.origin();
  return count_walls((a.x - o.x) / r, (a.y - o.y) / r, (b.x - o.x) / r, (b.y - o.y) / r, affordable + 1) <= affordable;
}

int RadioModel::count_walls(double ax, double ay, double bx, double by, int stop_at) const {
  // One direction for both: a ray that passes exactly through a cell corner
  // steps into one of the two cells beside it, and which one depends on the
  // direction; walking a-b and b-a alike keeps the link symmetric (what the
  // OC hears of an agent, the agent hears of the OC).
  if (bx < ax || (bx == ax && by < ay)) std::swap(ax, bx), std::swap(ay, by);
  // Amanatides-Woo traversal of every cell the segment passes through, in
  // cell coordinates (x = col, y = row, cell (c, r) spans [c, c+1) x [r, r+1)).
  const int w = grid_.width(), h = grid_.height();
  const uint8_t* free = grid_.free_mask().data();
  int cx = static_cast<int>(std::floor(ax)), cy = static_cast<int>(std::floor(ay));
  const int ex = static_cast<int>(std::floor(bx)), ey = static_cast<int>(std::floor(by));
  const double dx = bx - ax, dy = by - ay;
  const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double tdx = dx != 0 ? std::abs(1.0 / dx) : inf;
  const double tdy = dy != 0 ? std::abs(1.0 / dy) : inf;
  double tmx = dx != 0 ? ((dx > 0 ? (cx + 1 - ax) : (ax - cx)) * tdx) : inf;
  double tmy = dy != 0 ? ((dy > 0 ? (cy + 1 - ay) : (ay - cy)) * tdy) : inf;
  int walls = 0;
  bool in_wall = false;
  const int steps = std::abs(ex - cx) + std::abs(ey - cy);
  for (int i = 0;; ++i) {
    const bool inside = cx >= 0 && cy >= 0 && cx < w && cy < h;
    const bool blocked = inside && !free[static_cast<std::size_t>(cy) * w + cx];
    if (blocked && !in_wall && ++walls >= stop_at) return walls;
    in_wall = blocked;
    if (i >= steps) break;
    if (tmx < tmy) {
      cx += sx;
      tmx += tdx;
    } else {
      cy += sy;
      tmy += tdy;
    }
  }
  return walls;
}

int RadioModel::walls_between(Point2 a, Point2 b) const {
  const double r = grid_.resolution();
  const Point2 o = grid_.origin();
  return count_walls((a.x - o.x) / r, (a.y - o.y) / r, (b.x - o.x) / r, (b.y - o.y) / r,
                     std::numeric_limits<int>::max());
}

double RadioModel::received_dbm(Point2 a, Point2 b) const {
  const double d = std::hypot(b.x - a.x, b.y - a.y);
  return received_for(d, walls_between(a, b));
}

void RadioModel::coverage(Point2 tx, Mask& mask) const {
  if (mask.frame() != grid_.frame() || !mask.filled()) mask = Mask(grid_.frame());
  std::fill(mask.begin(), mask.end(), 0);
  const double res = grid_.resolution();
  const Point2 o = grid_.origin();
  const double range = free_range_m_;
  if (range <= 0) return;
  const double ax = (tx.x - o.x) / res, ay = (tx.y - o.y) / res;
  // Clamped to the grid before any cast (a huge link budget's range would
  // overflow int).
  const double range_cells = std::min(range / res + 1.0, static_cast<double>(grid_.width() + grid_.height()) + 1.0);
  const int c0 = std::max(0, static_cast<int>(std::floor(ax - range_cells)));
  const int c1 = std::min(grid_.width() - 1, static_cast<int>(std::ceil(ax + range_cells)));
  const int r0 = std::max(0, static_cast<int>(std::floor(ay - range_cells)));
  const int r1 = std::min(grid_.height() - 1, static_cast<int>(std::ceil(ay + range_cells)));
  const uint8_t* free = grid_.free_mask().data();
  const int w = grid_.width();
  const double sens = params_.sensitivity_dbm;
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      if (!free[i]) continue;
      // Same arithmetic as linked(tx, cell_center) so both always agree.
      const Point2 p = grid_.cell_center(Cell{r, c});
      const double d = std::hypot(p.x - tx.x, p.y - tx.y);
      const double clear = received_without_walls(d);
      if (clear < sens) continue;
      // Walls this link can afford (same arithmetic as received_for); counting stops one past them.
      const int affordable = affordable_walls(clear);
      if (affordable >= params_.max_walls ||
          count_walls(ax, ay, (p.x - o.x) / res, (p.y - o.y) / res, affordable + 1) <= affordable)
        mask[i] = 1;
    }
  }
}

}  // namespace gather
