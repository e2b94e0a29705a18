// LcmRobotLink and the robot interface's conversions: the only code that
// sees the generated robot_pose_t, nav_command_t, nav_status_t and robot_scan_t.
#include "gather_agent/transport/lcm_robot.hpp"

#include <lcm/lcm.h>
#include <poll.h>

#include <gather_lcm/nav_command_t.hpp>
#include <gather_lcm/nav_status_t.hpp>
#include <gather_lcm/robot_pose_t.hpp>
#include <gather_lcm/robot_scan_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "envelope.hpp"
#include "gather_agent/lcm_open.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

static_assert(gather_lcm::nav_command_t::MAX_WAYPOINTS == kMaxNavWaypoints, "command size differs from the wire type");
static_assert(gather_lcm::nav_status_t::MAX_WAYPOINTS == kMaxNavWaypoints, "status size differs from the wire type");
static_assert(gather_lcm::robot_scan_t::MAX_RAYS == kMaxScanRays, "scan size differs from the wire type");

// Bytes: the largest robot message (a command of 256 waypoints, a scan of
// 2048 rays) fits.
constexpr std::size_t kRobotBuffer = 16384;
// Messages held between two drains: an agent drains every few ms and its
// robot reports at 10-50 Hz; gather_world takes a command per agent a tick.
constexpr std::size_t kAgentQueue = 16, kRobotsQueue = 1024;

// The wire objects decoded into and encoded from (kept: their arrays keep
// their capacity, so converting allocates nothing after the first message).
struct RobotWire {
  gather_lcm::nav_command_t command;
  gather_lcm::nav_status_t status;
  gather_lcm::robot_pose_t pose;
  gather_lcm::robot_scan_t scan;
};
RobotWire& robot_wire() {
  static RobotWire w;
  return w;
}

template <typename T>
bool encode_wire(const T& w, std::vector<uint8_t>& out) {
  const int n = w.getEncodedSize();
  if (n < 0) return false;
  out.resize(static_cast<std::size_t>(n));
  return w.encode(out.data(), 0, n) == n;
}

NavState state_from_wire(int8_t s) { return static_cast<NavState>(s); }

void handler(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  static_cast<LcmRobotLink*>(user)->on_message(channel, rbuf->data, static_cast<int>(rbuf->data_size));
}

}  // namespace

bool encode_robot(const NavCommand& m, std::vector<uint8_t>& out) {
  if (m.n > kMaxNavWaypoints) return false;
  gather_lcm::nav_command_t& w = robot_wire().command;
  w.schema_version = gather_lcm::nav_command_t::SCHEMA_VERSION;
  w.agent = m.agent;
  w.tick = m.tick;
  w.command = m.id;
  w.kind = m.kind == NavCommand::Kind::kGo ? gather_lcm::nav_command_t::GO : gather_lcm::nav_command_t::STOP;
  w.n = static_cast<int16_t>(m.n);
  w.x.resize(m.n), w.y.resize(m.n), w.after.resize(m.n), w.tolerance.resize(m.n);
  for (std::size_t i = 0; i < m.n; ++i)
    w.x[i] = m.points[i].x, w.y[i] = m.points[i].y, w.after[i] = m.after[i], w.tolerance[i] = m.tolerance[i];
  return encode_wire(w, out);
}

bool encode_robot(const RobotPose& m, std::vector<uint8_t>& out) {
  gather_lcm::robot_pose_t& w = robot_wire().pose;
  w.schema_version = gather_lcm::robot_pose_t::SCHEMA_VERSION;
  w.agent = m.agent;
  w.tick = m.tick;
  w.stamp = m.stamp;
  w.x = m.at.x, w.y = m.at.y, w.theta = m.heading;
  w.v = m.v, w.w = m.w, w.sigma = m.sigma;
  return encode_wire(w, out);
}

bool encode_robot(const NavStatus& m, std::vector<uint8_t>& out) {
  if (m.reached > kMaxNavWaypoints) return false;
  gather_lcm::nav_status_t& w = robot_wire().status;
  w.schema_version = gather_lcm::nav_status_t::SCHEMA_VERSION;
  w.agent = m.agent;
  w.tick = m.tick;
  w.stamp = m.stamp;
  w.command = m.command;
  w.state = static_cast<int8_t>(m.state);
  w.reached = static_cast<int16_t>(m.reached);
  w.reached_at.assign(m.reached_at, m.reached_at + m.reached);
  w.has_eta = m.has_eta;
  w.eta = m.eta;
  w.contacts = m.contacts;
  return encode_wire(w, out);
}

bool encode_robot(const RobotScan& m, std::vector<uint8_t>& out) {
  if (m.rays < 1 || m.rays > kMaxScanRays) return false;
  gather_lcm::robot_scan_t& w = robot_wire().scan;
  w.schema_version = gather_lcm::robot_scan_t::SCHEMA_VERSION;
  w.agent = m.agent;
  w.tick = m.tick;
  w.stamp = m.stamp;
  w.x = m.at.x, w.y = m.at.y, w.theta = m.heading;
  w.angle_min = m.angle_min, w.angle_increment = m.angle_increment, w.range_max = m.range_max;
  w.rays = static_cast<int16_t>(m.rays);
  w.ranges.assign(m.ranges, m.ranges + m.rays);
  return encode_wire(w, out);
}

RobotDecoded decode_robot(const void* data, int size, NavCommand& m) {
  gather_lcm::nav_command_t& w = robot_wire().command;
  if (safe_decode(w, data, size) != size) return RobotDecoded::kUndecodable;
  if (w.schema_version != gather_lcm::nav_command_t::SCHEMA_VERSION) return RobotDecoded::kWrongVersion;
  const bool go = w.kind == gather_lcm::nav_command_t::GO, stop = w.kind == gather_lcm::nav_command_t::STOP;
  if (w.agent < 0 || w.agent >= kMaxTeam || w.command <= 0 || !(go || stop) ||
      (go && (w.n < 1 || w.n > kMaxNavWaypoints)) || (stop && w.n != 0))
    return RobotDecoded::kOutOfRange;
  for (std::size_t i = 0; i < static_cast<std::size_t>(w.n); ++i)
    if (!std::isfinite(w.x[i]) || !std::isfinite(w.y[i]) || !(w.after[i] >= 0 && w.after[i] <= 1e9) ||
        !(w.tolerance[i] > 0 && w.tolerance[i] <= 1e3))
      return RobotDecoded::kOutOfRange;
  m.agent = w.agent;
  m.tick = w.tick;
  m.id = w.command;
  m.kind = go ? NavCommand::Kind::kGo : NavCommand::Kind::kStop;
  m.n = static_cast<uint16_t>(w.n);
  for (std::size_t i = 0; i < m.n; ++i)
    m.points[i] = Point2{w.x[i], w.y[i]}, m.after[i] = w.after[i], m.tolerance[i] = w.tolerance[i];
  return RobotDecoded::kOk;
}

RobotDecoded decode_robot(const void* data, int size, RobotPose& m) {
  gather_lcm::robot_pose_t& w = robot_wire().pose;
  if (safe_decode(w, data, size) != size) return RobotDecoded::kUndecodable;
  if (w.schema_version != gather_lcm::robot_pose_t::SCHEMA_VERSION) return RobotDecoded::kWrongVersion;
  if (w.agent < 0 || w.agent >= kMaxTeam) return RobotDecoded::kOutOfRange;
  m.agent = w.agent;
  m.tick = w.tick;
  m.stamp = w.stamp;
  m.at = Point2{w.x, w.y};
  m.heading = w.theta, m.v = w.v, m.w = w.w, m.sigma = w.sigma;
  return RobotDecoded::kOk;
}

RobotDecoded decode_robot(const void* data, int size, NavStatus& m) {
  gather_lcm::nav_status_t& w = robot_wire().status;
  if (safe_decode(w, data, size) != size) return RobotDecoded::kUndecodable;
  if (w.schema_version != gather_lcm::nav_status_t::SCHEMA_VERSION) return RobotDecoded::kWrongVersion;
  if (w.agent < 0 || w.agent >= kMaxTeam || w.command < 0 || w.state < gather_lcm::nav_status_t::IDLE ||
      w.state > gather_lcm::nav_status_t::BLOCKED || w.reached < 0 || w.reached > kMaxNavWaypoints || w.contacts < 0)
    return RobotDecoded::kOutOfRange;
  m.agent = w.agent;
  m.tick = w.tick;
  m.stamp = w.stamp;
  m.command = w.command;
  m.state = state_from_wire(w.state);
  m.reached = static_cast<uint16_t>(w.reached);
  // The decoder keeps an earlier message's array for a count of 0: the
  // counted entries only.
  std::copy(w.reached_at.begin(), w.reached_at.begin() + w.reached, m.reached_at);
  m.has_eta = w.has_eta;
  m.eta = w.eta;
  m.contacts = w.contacts;
  return RobotDecoded::kOk;
}

RobotDecoded decode_robot(const void* data, int size, RobotScan& m) {
  gather_lcm::robot_scan_t& w = robot_wire().scan;
  if (safe_decode(w, data, size) != size) return RobotDecoded::kUndecodable;
  if (w.schema_version != gather_lcm::robot_scan_t::SCHEMA_VERSION) return RobotDecoded::kWrongVersion;
  if (w.agent < 0 || w.agent >= kMaxTeam || w.rays < 1 || w.rays > kMaxScanRays || !std::isfinite(w.x) ||
      !std::isfinite(w.y) || !std::isfinite(w.theta) || !std::isfinite(w.angle_min) ||
      !std::isfinite(w.angle_increment) || !(w.range_max > 0 && w.range_max <= 1e3))
    return RobotDecoded::kOutOfRange;
  m.agent = w.agent;
  m.tick = w.tick;
  m.stamp = w.stamp;
  m.at = Point2{w.x, w.y};
  m.heading = w.theta;
  m.angle_min = w.angle_min, m.angle_increment = w.angle_increment, m.range_max = w.range_max;
  m.rays = static_cast<uint16_t>(w.rays);
  std::copy(w.ranges.begin(), w.ranges.begin() + w.rays, m.ranges);
  return RobotDecoded::kOk;
}

namespace {

std::vector<std::string> channel_names(const std::vector<int>& ids) {
  std::vector<std::string> names;
  for (int id : ids)
    names.insert(names.end(),
                 {robot_command_channel(id), robot_pose_channel(id), robot_status_channel(id), robot_scan_channel(id)});
  return names;
}

}  // namespace

LcmRobotLink::LcmRobotLink(const std::string& url, Side side, std::vector<int> ids, std::optional<FleetKey> key)
    : side_(side),
      ids_(std::move(ids)),
      auth_(std::move(key), channel_names(ids_), kMaxTeam + 1),
      buffer_(kRobotBuffer) {
  std::string error;
  lcm_ = open_lcm_c(url, &error);
  if (!lcm_) throw Error("--robot-url", error);
  subscribe();
}

LcmRobotLink::LcmRobotLink(lcm_t* shared, Side side, std::vector<int> ids, std::optional<FleetKey> key)
    : lcm_(shared),
      owned_(false),
      side_(side),
      ids_(std::move(ids)),
      auth_(std::move(key), channel_names(ids_), kMaxTeam + 1),
      buffer_(kRobotBuffer) {
  subscribe();
}

void LcmRobotLink::subscribe() {
  auth_.in_order_only();  // commands, statuses and poses supersede each other: never one that arrives late
  envelopes_ = std::make_unique<Envelopes>(auth_, kRobotBuffer);
  for (int id : ids_) {
    command_channels_.push_back(robot_command_channel(id));
    pose_channels_.push_back(robot_pose_channel(id));
    status_channels_.push_back(robot_status_channel(id));
    scan_channels_.push_back(robot_scan_channel(id));
  }
  if (!ids_.empty()) auth_.reserve(*std::max_element(ids_.begin(), ids_.end()) + 1);
  if (side_ == Side::kAgent)
    poses_.reserve(kAgentQueue), statuses_.reserve(kAgentQueue);
  else if (side_ == Side::kRobots)
    commands_.reserve(kRobotsQueue);
  else
    scans_.reserve(4 * ids_.size());
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    if (side_ == Side::kAgent) {
      lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, pose_channels_[i].c_str(), handler, this), 1000);
      lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, status_channels_[i].c_str(), handler, this), 1000);
    } else if (side_ == Side::kRobots) {
      lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, command_channels_[i].c_str(), handler, this), 1000);
    } else {
      lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, scan_channels_[i].c_str(), handler, this), 100);
    }
  }
}

LcmRobotLink::~LcmRobotLink() {
  if (lcm_ && owned_) lcm_destroy(lcm_);
}

int LcmRobotLink::id_index(int agent) const {
  const auto it = std::find(ids_.begin(), ids_.end(), agent);
  return it == ids_.end() ? -1 : static_cast<int>(it - ids_.begin());
}

bool LcmRobotLink::seal_and_publish(const std::string& channel, int16_t sender) {
  const int n = envelopes_->seal(channel.c_str(), sender, buffer_.data(), static_cast<int>(buffer_.size()));
  if (n < 0 || lcm_publish(lcm_, channel.c_str(), envelopes_->bytes(), static_cast<unsigned>(n)) != 0)
    return ++publish_failures_, false;
  ++sent_;
  return true;
}

void LcmRobotLink::send(const NavCommand& c) {
  const int i = id_index(c.agent);
  if (side_ != Side::kAgent || i < 0 || !encode_robot(c, buffer_)) return void(++publish_failures_);
  seal_and_publish(command_channels_[static_cast<std::size_t>(i)], c.agent);
}

bool LcmRobotLink::publish(const RobotPose& p) {
  const int i = id_index(p.agent);
  if (side_ != Side::kRobots || i < 0 || !encode_robot(p, buffer_)) return ++publish_failures_, false;
  return seal_and_publish(pose_channels_[static_cast<std::size_t>(i)], p.agent);
}

bool LcmRobotLink::publish(const NavStatus& s) {
  const int i = id_index(s.agent);
  if (side_ != Side::kRobots || i < 0 || !encode_robot(s, buffer_)) return ++publish_failures_, false;
  return seal_and_publish(status_channels_[static_cast<std::size_t>(i)], s.agent);
}

bool LcmRobotLink::publish(const RobotScan& s) {
  const int i = id_index(s.agent);
  if (side_ != Side::kRobots || i < 0 || !encode_robot(s, buffer_)) return ++publish_failures_, false;
  return seal_and_publish(scan_channels_[static_cast<std::size_t>(i)], s.agent);
}

int LcmRobotLink::fileno() const { return lcm_get_fileno(lcm_); }

bool LcmRobotLink::handle(int timeout_ms) {
  pollfd fd{fileno(), POLLIN, 0};
  if (::poll(&fd, 1, timeout_ms) <= 0) return false;
  for (int round = 0; round < 1000; ++round) {
    lcm_handle(lcm_);
    if (::poll(&fd, 1, 0) <= 0) break;
  }
  return true;
}

void LcmRobotLink::on_message(const char* channel, const void* data, int size) {
  switch (envelopes_->open(channel, data, size)) {
    case Envelopes::Opened::kOk: break;
    case Envelopes::Opened::kUndecodable: return void(++refused_.undecodable);
    case Envelopes::Opened::kOutOfRange: return void(++refused_.out_of_range);
    case Envelopes::Opened::kWrongVersion: return void(++refused_.wrong_version);
    case Envelopes::Opened::kRejected: return;  // counted by FleetAuth
  }
  const uint8_t* p = envelopes_->payload();
  const int n = envelopes_->payload_size();
  const int16_t sender = envelopes_->sender();
  auto count = [&](RobotDecoded d) {
    switch (d) {
      case RobotDecoded::kOk: return true;
      case RobotDecoded::kUndecodable: ++refused_.undecodable; break;
      case RobotDecoded::kWrongVersion: ++refused_.wrong_version; break;
      case RobotDecoded::kOutOfRange: ++refused_.out_of_range; break;
    }
    return false;
  };
  // The message's agent must be its channel's and its signed sender; it
  // goes into `queue` (up to its capacity).
  auto take = [&](auto& queue, int id) {
    if (queue.size() >= queue.capacity()) return void(++refused_.queue_full);
    queue.emplace_back();
    if (!count(decode_robot(p, n, queue.back()))) return queue.pop_back();
    if (queue.back().agent != id || sender != id) {
      queue.pop_back();
      return auth_.count_wrong_sender();
    }
  };
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    if (side_ == Side::kAgent && pose_channels_[i] == channel) return take(poses_, ids_[i]);
    if (side_ == Side::kAgent && status_channels_[i] == channel) return take(statuses_, ids_[i]);
    if (side_ == Side::kViewer && scan_channels_[i] == channel) return take(scans_, ids_[i]);
    if (side_ == Side::kRobots && command_channels_[i] == channel) return take(commands_, ids_[i]);
  }
}

}  // namespace agent
}  // namespace gather
