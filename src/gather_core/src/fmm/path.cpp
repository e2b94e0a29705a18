#include "gather_core/fmm/path.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace fmm {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

// Position in cell units: cell (r, c) spans [c, c+1) x [r, r+1).
struct Q {
  double x, y;
};

Q to_cells(const FastMarching& fm, Point2 p) {
  return Q{(p.x - fm.origin().x) / fm.resolution(), (p.y - fm.origin().y) / fm.resolution()};
}
Point2 to_map(const FastMarching& fm, Q q) {
  return Point2{fm.origin().x + q.x * fm.resolution(), fm.origin().y + q.y * fm.resolution()};
}
Cell cell_of(Q q) { return Cell{static_cast<int>(std::floor(q.y)), static_cast<int>(std::floor(q.x))}; }
bool finite_q(Q q) { return std::abs(q.x) < 1e9 && std::abs(q.y) < 1e9; }

float time_of(const FastMarching& fm, Cell c) { return fm.traversable(c) ? fm.padded_times()[fm.padded(c)] : kInfF; }

// Bilinear weights over the four cell centres around q; unreached centres drop
// out, and so does the centre diagonal to q's own cell when an obstacle corner
// stands between them (the front does not cross there).
template <class F>
bool bilinear(const FastMarching& fm, Q q, F&& visit) {
  const double gx = q.x - 0.5, gy = q.y - 0.5;
  const int c0 = static_cast<int>(std::floor(gx)), r0 = static_cast<int>(std::floor(gy));
  const double fx = gx - c0, fy = gy - r0;
  const Cell own{static_cast<int>(std::floor(q.y)), static_cast<int>(std::floor(q.x))};
  double wsum = 0.0;
  double w[4];
  Cell cells[4];
  for (int k = 0; k < 4; ++k) {
    const int dr = k >> 1, dc = k & 1;
    cells[k] = Cell{r0 + dr, c0 + dc};
    const double wk = (dr ? fy : 1.0 - fy) * (dc ? fx : 1.0 - fx);
    const bool diagonal = cells[k].row != own.row && cells[k].col != own.col;
    const bool hidden =
        diagonal && (!fm.traversable(Cell{own.row, cells[k].col}) || !fm.traversable(Cell{cells[k].row, own.col}));
    w[k] = !hidden && time_of(fm, cells[k]) < kInfF ? wk : 0.0;
    wsum += w[k];
  }
  if (!(wsum > 1e-12)) return false;
  for (int k = 0; k < 4; ++k)
    if (w[k] > 0.0) visit(cells[k], w[k] / wsum);
  return true;
}

double interp_time(const FastMarching& fm, Q q) {
  double v = 0.0;
  if (!bilinear(fm, q, [&](Cell c, double w) { v += w * time_of(fm, c); })) {
    // Only the own cell may be reached (a cell between obstacles).
    const float t = time_of(fm, cell_of(q));
    return t < kInfF ? t : kUnreached;
  }
  return v;
}

// Upwind gradient of T at a cell centre [s per cell].
void cell_gradient(const FastMarching& fm, Cell c, double& gx, double& gy) {
  const float t = time_of(fm, c);
  auto axis = [&](Cell lo, Cell hi) {
    const float l = time_of(fm, lo), h = time_of(fm, hi);
    if (!(std::min(l, h) < t)) return 0.0;
    return l < h ? static_cast<double>(t - l) : static_cast<double>(h - t);
  };
  gx = axis(Cell{c.row, c.col - 1}, Cell{c.row, c.col + 1});
  gy = axis(Cell{c.row - 1, c.col}, Cell{c.row + 1, c.col});
}

// Two cells a step may join: the same, 4-adjacent, or diagonal with both cells between free.
bool step_allowed(const FastMarching& fm, Cell a, Cell b) {
  const int dr = b.row - a.row, dc = b.col - a.col;
  if (std::abs(dr) > 1 || std::abs(dc) > 1) return false;
  if (dr != 0 && dc != 0) return fm.traversable(Cell{a.row + dr, a.col}) && fm.traversable(Cell{a.row, a.col + dc});
  return true;
}

// Source whose seed is cell c (its time came straight from that source), or -1.
int seed_source(const FastMarching& fm, Cell c) {
  const std::size_t p = fm.padded(c);
  const float t = fm.padded_times()[p];
  const int lab = fm.label(c);
  for (const auto& s : fm.seeds())
    if (s.index == p && s.time == t && (lab < 0 || lab == s.source)) return s.source;
  return -1;
}

}  // namespace

double interpolated_time(const FastMarching& fm, Point2 p) {
  const Q q = to_cells(fm, p);
  if (!finite_q(q)) return kUnreached;
  return interp_time(fm, q);
}

std::vector<Point2> descend(const FastMarching& fm, Point2 from, const PathOptions& options) {
  const Q q0 = to_cells(fm, from);
  if (!finite_q(q0) || !fm.contains(cell_of(q0)))
    throw Error("path", "start [" + std::to_string(from.x) + ", " + std::to_string(from.y) + "] m is off the map");
  Cell cur = cell_of(q0);
  if (!fm.traversable(cur)) throw Error("path", "start is in an obstacle");
  if (!(time_of(fm, cur) < kInfF)) throw Error("path", "start was not reached by the last solve");
  const double step = std::clamp(options.step, 0.01, 0.5);

  std::vector<Point2> path{from};
  Q q = q0;
  double tq = interp_time(fm, q);
  // Each step lowers T; a bound on steps guards against a field that does not.
  const std::size_t max_steps = 64 + static_cast<std::size_t>(8.0 * (fm.width() + fm.height()) / step) * 4;
  for (std::size_t it = 0; it < max_steps; ++it) {
    const int src = seed_source(fm, cur);
    if (src >= 0) {
      const Source& s = fm.sources()[static_cast<std::size_t>(src)];
      path.push_back(s.is_point ? s.point : to_map(fm, Q{s.cell.col + 0.5, s.cell.row + 0.5}));
      return path;
    }
    // Gradient step.
    double gx = 0.0, gy = 0.0;
    bilinear(fm, q, [&](Cell c, double w) {
      double cx, cy;
      cell_gradient(fm, c, cx, cy);
      gx += w * cx;
      gy += w * cy;
    });
    const double norm = std::hypot(gx, gy);
    bool moved = false;
    if (norm > 1e-12) {
      const Q qn{q.x - step * gx / norm, q.y - step * gy / norm};
      const Cell cn = cell_of(qn);
      if (fm.traversable(cn) && time_of(fm, cn) < kInfF && step_allowed(fm, cur, cn)) {
        const double tn = interp_time(fm, qn);
        if (tn < tq) {
          q = qn;
          tq = tn;
          cur = cn;
          moved = true;
        }
      }
    }
    if (!moved) {
      // Fallback: the centre of the lowest cell among the current one and its
      // 8 neighbours that is below the current interpolated time.
      Cell best{};
      float bt = static_cast<float>(tq);
      bool found = false;
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const Cell n{cur.row + dr, cur.col + dc};
          const float tn = time_of(fm, n);
          if (tn < bt && step_allowed(fm, cur, n)) {
            bt = tn;
            best = n;
            found = true;
          }
        }
      }
      if (!found) break;
      q = Q{best.col + 0.5, best.row + 0.5};
      tq = bt;
      cur = best;
    }
    path.push_back(to_map(fm, q));
  }
  throw Error("path", "gradient descent did not reach a source (time field trimmed or inconsistent)");
}

double path_length(const std::vector<Point2>& path) {
  double len = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) len += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  return len;
}

std::vector<double> path_arcs(const std::vector<Point2>& path) {
  std::vector<double> arcs(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i)
    arcs[i] = arcs[i - 1] + std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  return arcs;
}

Point2 point_at_arc(const std::vector<Point2>& path, const std::vector<double>& arcs, double s) {
  if (path.empty()) return Point2{};
  if (path.size() == 1 || s <= 0) return path.front();
  if (s >= arcs.back()) return path.back();
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(arcs.begin(), arcs.end(), s) - arcs.begin()) - 1;
  const double len = arcs[i + 1] - arcs[i];
  const double f = len > 0 ? (s - arcs[i]) / len : 0.0;
  return Point2{path[i].x + f * (path[i + 1].x - path[i].x), path[i].y + f * (path[i + 1].y - path[i].y)};
}

Point2 ArcWalker::at(double s) {
  if (path_.empty()) return Point2{};
  if (path_.size() == 1 || s <= 0) return path_.front();
  if (s >= arcs_.back()) return path_.back();
  if (next_ > 0 && arcs_[next_ - 1] > s)  // went back: search again
    next_ = static_cast<std::size_t>(std::upper_bound(arcs_.begin(), arcs_.end(), s) - arcs_.begin());
  // Forward: a few steps, then a binary search (a walk that skips far ahead
  // costs no more than one that samples every piece).
  for (int steps = 0; next_ < arcs_.size() && arcs_[next_] <= s; ++next_)
    if (++steps == 8) {
      next_ = static_cast<std::size_t>(
          std::upper_bound(arcs_.begin() + static_cast<std::ptrdiff_t>(next_), arcs_.end(), s) - arcs_.begin());
      break;
    }
  const std::size_t i = next_ - 1;
  const double len = arcs_[i + 1] - arcs_[i];
  const double f = len > 0 ? (s - arcs_[i]) / len : 0.0;
  return Point2{path_[i].x + f * (path_[i + 1].x - path_[i].x), path_[i].y + f * (path_[i + 1].y - path_[i].y)};
}

double geodesic_time(FastMarching& fm, Point2 a, Point2 b, Order order) {
  // Reused between calls: a geodesic query allocates nothing once warm.
  static thread_local SolveOptions o;
  o.order = order;
  o.labels = false;
  o.targets.clear();
  const Q qb = to_cells(fm, b);
  if (!finite_q(qb)) return kUnreached;
  const Cell cb = cell_of(qb);
  if (!fm.traversable(cb)) return kUnreached;
  const int dr[5] = {0, 1, -1, 0, 0};
  const int dc[5] = {0, 0, 0, 1, -1};
  for (int k = 0; k < 5; ++k) {
    const Cell n{cb.row + dr[k], cb.col + dc[k]};
    if (fm.traversable(n)) o.targets.push_back(n);
  }
  static thread_local std::vector<Source> src(1);
  src[0] = Source::at_point(a);
  fm.solve(src, o);
  return fm.time_at(b);
}

}  // namespace fmm
}  // namespace gather
