#include "gather_agent/motion/robot_base.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {

std::string robot_pose_channel(int agent) { return "GATHER_ROBOT_POSE_" + std::to_string(agent); }
std::string robot_command_channel(int agent) { return "GATHER_ROBOT_CMD_" + std::to_string(agent); }
std::string robot_status_channel(int agent) { return "GATHER_ROBOT_STATUS_" + std::to_string(agent); }
std::string robot_scan_channel(int agent) { return "GATHER_ROBOT_SCAN_" + std::to_string(agent); }

void check_params(const RobotBaseParams& p) {
  require_in_range(p.silence_s, 0.2, 600, "robot base params", "silence_s", " s");
  require_in_range(p.max_sigma_m, 0.01, 100, "robot base params", "max_sigma_m", " m");
  require_in_range(p.tolerance_m, 0.01, 10, "robot base params", "tolerance_m", " m");
  require_in_range(p.resend_s, 0.1, 60, "robot base params", "resend_s", " s");
}

RobotBase::RobotBase(const OccupancyGrid& grid, int agent, Point2 start, double speed, NavCommandSink& sink,
                     const RobotBaseParams& params)
    : grid_(grid), agent_(agent), speed_(speed), sink_(sink), params_(params), pose_(start) {
  check_params(params);
  legs_.resize(kMaxNavWaypoints);
  arrived_.resize(kMaxNavWaypoints);
  command_.agent = static_cast<int16_t>(agent);
  fault_text_.reserve(160);
}

bool RobotBase::on_free_space(Point2 p) const {
  const Cell c = grid_.world_to_cell(p);
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc) {
      const Cell n{c.row + dr, c.col + dc};
      if (grid_.contains(n) && grid_.free_mask()[grid_.index(n)]) return true;
    }
  return false;
}

void RobotBase::set_fault(BaseFault f, double now, const char* why) {
  if (f == fault_) return;
  fault_ = f;
  if (f == BaseFault::kNone) {
    fault_text_.clear();
    return;
  }
  ++counters_.faults;
  char line[160];
  std::snprintf(line, sizeof line, "robot %s at t = %.1f s: %s", base_fault_name(f), now, why);
  fault_text_ = line;
  if (first_fault_.empty()) first_fault_ = fault_text_;
}

void RobotBase::on_pose(const RobotPose& p, double now) {
  now_ = std::max(now_, now);
  if (!std::isfinite(p.at.x) || !std::isfinite(p.at.y) || !std::isfinite(p.heading) || !std::isfinite(p.v) ||
      !std::isfinite(p.stamp) || !on_free_space(p.at)) {
    ++counters_.bad_pose;
    set_fault(BaseFault::kOffMap, now,
              "its pose is not a number or off the map's free space; the last good one is kept");
    return;
  }
  if (!(p.sigma <= params_.max_sigma_m)) {
    ++counters_.lost_pose;
    set_fault(BaseFault::kLost, now, "its localisation is worse than max_sigma_m; the last good pose is kept");
    return;
  }
  ++counters_.poses;
  pose_ = p.at, heading_ = p.heading, v_ = p.v;
  heard_at_ = now;
  if (fault_ == BaseFault::kOffMap || fault_ == BaseFault::kLost || fault_ == BaseFault::kSilent)
    set_fault(BaseFault::kNone, now, "");
}

void RobotBase::on_status(const NavStatus& s, double now) {
  now_ = std::max(now_, now);
  if (!std::isfinite(s.stamp)) {
    ++counters_.bad_status;
    return;
  }
  heard_at_ = now;
  if (fault_ == BaseFault::kSilent) set_fault(BaseFault::kNone, now, "");
  contacts_ = std::max(contacts_, s.contacts);
  if (s.command != command_.id || command_.id == 0) {  // about another command (an older one, or none)
    ++counters_.stale_status;
    return;
  }
  // What it says must follow from what it said: reached waypoints only
  // grow, within the command, at times no later than the stamp.
  bool ok = s.reached <= n_ && s.reached >= reached_;
  for (uint16_t i = 0; ok && i < s.reached; ++i)
    ok = std::isfinite(s.reached_at[i]) && s.reached_at[i] <= s.stamp &&
         (i == 0 || s.reached_at[i] >= s.reached_at[i - 1]);
  if (command_.kind == NavCommand::Kind::kStop) ok = ok && s.reached == 0;
  if (!ok || (s.has_eta && !std::isfinite(s.eta))) {
    ++counters_.bad_status;
    return;
  }
  ++counters_.statuses;
  status_heard_at_ = now;
  // Robot clock -> mission time: the report's age at `now`.
  for (std::size_t i = reached_; i < s.reached; ++i)
    arrived_[i] = std::max(sent_at_, now - (s.stamp - s.reached_at[i]));
  reached_ = s.reached;
  state_ = command_.kind == NavCommand::Kind::kStop ? NavState::kIdle : s.state;
  if (state_ == NavState::kReached && reached_ < n_) state_ = NavState::kActive;  // not every waypoint: not done
  eta_ = s.has_eta ? now - (s.stamp - s.eta) : kNoEstimate;
}

void RobotBase::go(const Waypoint* legs, std::size_t n, double now) {
  if (n == 0 || n > static_cast<std::size_t>(kMaxNavWaypoints))
    throw Error("motion", "a command of " + std::to_string(n) + " waypoints, 1.." + std::to_string(kMaxNavWaypoints));
  now_ = std::max(now_, now);
  std::copy(legs, legs + n, legs_.begin());
  n_ = n, reached_ = 0, eta_ = kNoEstimate;
  state_ = NavState::kActive;
  status_heard_at_ = -1.0;
  ++command_.id;
  command_.kind = NavCommand::Kind::kGo;
  command_.n = static_cast<uint16_t>(n);
  for (std::size_t i = 0; i < n; ++i) {
    command_.points[i] = legs[i].point;
    command_.after[i] = std::max(0.0, legs[i].arrive - now);
    command_.tolerance[i] = legs[i].tolerance > 0 ? legs[i].tolerance : params_.tolerance_m;
  }
  sent_at_ = now;
  command_.tick = tick_;
  sink_.send(command_);
  ++counters_.commands;
  last_sent_ = now;
  ++revision_;
}

void RobotBase::stop(double now) {
  now_ = std::max(now_, now);
  n_ = reached_ = 0;
  state_ = NavState::kIdle;
  eta_ = kNoEstimate;
  ++command_.id;
  command_.kind = NavCommand::Kind::kStop;
  command_.n = 0;
  sent_at_ = now;
  command_.tick = tick_;
  sink_.send(command_);
  ++counters_.commands;
  last_sent_ = now;
  ++revision_;
}

void RobotBase::update(double now) {
  now_ = std::max(now_, now);
  // A command under way goes out again now and then (a robot that missed
  // it, or restarted, picks it up; the same id changes nothing).
  if (command_.id > 0 && (state_ == NavState::kActive || state_ == NavState::kBlocked) &&
      now - last_sent_ >= params_.resend_s) {
    command_.tick = tick_;
    for (std::size_t i = 0; i < command_.n; ++i) command_.after[i] = std::max(0.0, legs_[i].arrive - now);
    sink_.send(command_);
    ++counters_.commands;
    last_sent_ = now;
  }
  if (now - heard_at_ > params_.silence_s)
    set_fault(BaseFault::kSilent, now, "no pose or status from it for longer than silence_s");
  else if (command_.id > 0 && status_heard_at_ < 0 && now - sent_at_ > params_.silence_s)
    set_fault(BaseFault::kSilent, now, "no status for its current command for longer than silence_s");
}

double RobotBase::arrival_estimate() const {
  if (n_ == 0) return kNoEstimate;
  if (reached_ == n_) return arrived_[n_ - 1];
  if (eta_ < kNoEstimate) return eta_;
  // Its own: the straight way through the waypoints left at the team speed.
  double left = std::hypot(legs_[reached_].point.x - pose_.x, legs_[reached_].point.y - pose_.y);
  for (std::size_t i = reached_ + 1; i < n_; ++i)
    left += std::hypot(legs_[i].point.x - legs_[i - 1].point.x, legs_[i].point.y - legs_[i - 1].point.y);
  return std::max(legs_[n_ - 1].arrive, now_ + left / speed_);
}

std::size_t RobotBase::path(Point2* out, std::size_t max) const {
  if (n_ == 0 || max < 2) return 0;
  std::size_t k = 0;
  out[k++] = pose_;
  for (std::size_t i = reached_; i < n_ && k < max; ++i) out[k++] = legs_[i].point;
  return k >= 2 ? k : 0;
}

}  // namespace agent
}  // namespace gather
