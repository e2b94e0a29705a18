// transport/lcm_robot: the robot interface's LCM edge. encode_robot /
// decode_robot round trips of every message (a command's per-waypoint
// tolerance included); what does not decode, carries another schema version
// or holds counts, states, kinds or tolerances out of range is refused by
// its reason, while a pose that is not a number decodes (its robot's fault,
// for RobotBase to judge). LcmRobotLink over memq:// (inside this process,
// no network; memq is one queue per lcm_t, so two links cannot hear each
// other there: envelopes signed by hand are handed to a link's handler, as
// tests/agent/fleet_auth_test.cpp does for the fleet): a signed message
// arrives, one signed by another sender or naming another agent than its
// channel is counted wrong_sender, a replay is rejected. Two links over UDP
// multicast only inside tools/netns-run (GATHER_NETNS=1), never on the host.
#include "gather_agent/transport/lcm_robot.hpp"

#include <gtest/gtest.h>

#include <gather_lcm/envelope_t.hpp>
#include <gather_lcm/nav_command_t.hpp>
#include <gather_lcm/nav_status_t.hpp>
#include <gather_lcm/robot_pose_t.hpp>
#include <gather_lcm/robot_scan_t.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gather_agent/messages.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <typename T>
std::vector<uint8_t> encoded(const T& msg) {
  std::vector<uint8_t> b(static_cast<std::size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(b.data(), 0, static_cast<int>(b.size())), static_cast<int>(b.size()));
  return b;
}

FleetKey test_key(int16_t id = 7, uint8_t fill = 0x5a) {
  FleetKey k;
  k.id = id;
  k.key.fill(fill);
  return k;
}

// --- The messages ---------------------------------------------------------

NavCommand three_waypoints() {
  NavCommand c;
  c.agent = 5, c.tick = 42, c.id = 7, c.kind = NavCommand::Kind::kGo, c.n = 3;
  c.points[0] = Point2{1.25, -3.5}, c.points[1] = Point2{2.5, 4.75}, c.points[2] = Point2{19.05, 0.25};
  c.after[0] = 0.0, c.after[1] = 3.5, c.after[2] = 12.25;
  c.tolerance[0] = 0.25, c.tolerance[1] = 1.0, c.tolerance[2] = 0.1;  // a goal, a place, a tight goal
  return c;
}

RobotPose a_pose(int16_t agent = 3) {
  RobotPose p;
  p.agent = agent, p.tick = -1, p.stamp = 1234.5;
  p.at = Point2{5.5, 17.75};
  p.heading = -2.5, p.v = 0.4, p.w = -0.3, p.sigma = 0.05;
  return p;
}

NavStatus a_status(int16_t agent = 3) {
  NavStatus s;
  s.agent = agent, s.tick = 9, s.stamp = 50.5, s.command = 4, s.state = NavState::kFailed;
  s.reached = 2, s.reached_at[0] = 40.25, s.reached_at[1] = 45.5;
  s.has_eta = true, s.eta = 60.75, s.contacts = 3;
  return s;
}

// Valid wire messages, to break one field at a time.
gather_lcm::nav_command_t wire_go(int n = 2) {
  gather_lcm::nav_command_t w{};
  w.schema_version = gather_lcm::nav_command_t::SCHEMA_VERSION;
  w.agent = 3, w.tick = 5, w.command = 2, w.kind = gather_lcm::nav_command_t::GO;
  w.n = static_cast<int16_t>(n);
  for (int i = 0; i < n; ++i) {
    w.x.push_back(1.0 + i), w.y.push_back(0.25), w.after.push_back(1.5 * i), w.tolerance.push_back(0.25);
  }
  return w;
}

gather_lcm::nav_status_t wire_status(int reached = 1) {
  gather_lcm::nav_status_t w{};
  w.schema_version = gather_lcm::nav_status_t::SCHEMA_VERSION;
  w.agent = 3, w.tick = 5, w.stamp = 10.0, w.command = 2, w.state = gather_lcm::nav_status_t::ACTIVE;
  w.reached = static_cast<int16_t>(reached);
  for (int i = 0; i < reached; ++i) w.reached_at.push_back(1.0 + i);
  w.has_eta = true, w.eta = 12.0, w.contacts = 0;
  return w;
}

gather_lcm::robot_pose_t wire_pose() {
  gather_lcm::robot_pose_t w{};
  w.schema_version = gather_lcm::robot_pose_t::SCHEMA_VERSION;
  w.agent = 3, w.tick = -1, w.stamp = 1.0, w.x = 1.0, w.y = 2.0;
  return w;
}

template <typename M, typename W>
RobotDecoded decode_wire(const W& w) {
  const std::vector<uint8_t> b = encoded(w);
  M m;
  return decode_robot(b.data(), static_cast<int>(b.size()), m);
}

TEST(LcmRobotCodec, ACommandSurvivesTheRoundTripWithEachWaypointsTolerance) {
  const NavCommand c = three_waypoints();
  std::vector<uint8_t> b;
  ASSERT_TRUE(encode_robot(c, b));
  NavCommand got;
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), got), RobotDecoded::kOk);
  EXPECT_EQ(got.agent, 5);
  EXPECT_EQ(got.tick, 42);
  EXPECT_EQ(got.id, 7);
  EXPECT_EQ(got.kind, NavCommand::Kind::kGo);
  ASSERT_EQ(got.n, 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(got.points[i].x, c.points[i].x) << i;
    EXPECT_EQ(got.points[i].y, c.points[i].y) << i;
    EXPECT_EQ(got.after[i], c.after[i]) << i;
    EXPECT_EQ(got.tolerance[i], c.tolerance[i]) << i;
  }
  // A stop: no waypoints.
  NavCommand stop;
  stop.agent = 5, stop.id = 8, stop.kind = NavCommand::Kind::kStop, stop.n = 0;
  ASSERT_TRUE(encode_robot(stop, b));
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), got), RobotDecoded::kOk);
  EXPECT_EQ(got.kind, NavCommand::Kind::kStop);
  EXPECT_EQ(got.id, 8);
  EXPECT_EQ(got.n, 0u);
  // The most waypoints a command holds, each its own tolerance.
  NavCommand full;
  full.agent = 1, full.id = 1, full.kind = NavCommand::Kind::kGo, full.n = kMaxNavWaypoints;
  for (int i = 0; i < kMaxNavWaypoints; ++i)
    full.points[i] = Point2{0.1 * i, -0.1 * i}, full.after[i] = i, full.tolerance[i] = 0.01 * (i + 1);
  ASSERT_TRUE(encode_robot(full, b));
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), got), RobotDecoded::kOk);
  ASSERT_EQ(got.n, kMaxNavWaypoints);
  for (std::size_t i = 0; i < kMaxNavWaypoints; ++i) {
    ASSERT_EQ(got.tolerance[i], full.tolerance[i]) << i;
    ASSERT_EQ(got.points[i].y, full.points[i].y) << i;
  }
  EXPECT_EQ(got.after[255], 255.0);
  // More than that does not encode.
  full.n = kMaxNavWaypoints + 1;
  EXPECT_FALSE(encode_robot(full, b));
}

TEST(LcmRobotCodec, APoseAndAStatusSurviveTheRoundTrip) {
  const RobotPose p = a_pose();
  std::vector<uint8_t> b;
  ASSERT_TRUE(encode_robot(p, b));
  RobotPose gp;
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), gp), RobotDecoded::kOk);
  EXPECT_EQ(gp.agent, 3);
  EXPECT_EQ(gp.tick, -1);
  EXPECT_EQ(gp.stamp, 1234.5);
  EXPECT_EQ(gp.at.x, 5.5);
  EXPECT_EQ(gp.at.y, 17.75);
  EXPECT_EQ(gp.heading, -2.5);
  EXPECT_EQ(gp.v, 0.4);
  EXPECT_EQ(gp.w, -0.3);
  EXPECT_EQ(gp.sigma, 0.05);

  const NavStatus s = a_status();
  ASSERT_TRUE(encode_robot(s, b));
  NavStatus gs;
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), gs), RobotDecoded::kOk);
  EXPECT_EQ(gs.agent, 3);
  EXPECT_EQ(gs.tick, 9);
  EXPECT_EQ(gs.stamp, 50.5);
  EXPECT_EQ(gs.command, 4);
  EXPECT_EQ(gs.state, NavState::kFailed);
  ASSERT_EQ(gs.reached, 2u);
  EXPECT_EQ(gs.reached_at[0], 40.25);
  EXPECT_EQ(gs.reached_at[1], 45.5);
  EXPECT_TRUE(gs.has_eta);
  EXPECT_EQ(gs.eta, 60.75);
  EXPECT_EQ(gs.contacts, 3);
  // Every state, as itself.
  for (const NavState st :
       {NavState::kIdle, NavState::kActive, NavState::kReached, NavState::kFailed, NavState::kBlocked}) {
    NavStatus one = s;
    one.state = st;
    ASSERT_TRUE(encode_robot(one, b));
    ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), gs), RobotDecoded::kOk);
    EXPECT_EQ(gs.state, st);
  }
  NavStatus too_many = s;
  too_many.reached = kMaxNavWaypoints + 1;
  EXPECT_FALSE(encode_robot(too_many, b));
}

TEST(LcmRobotCodec, TruncatedBytesAndAnotherTypeAreUndecodable) {
  std::vector<uint8_t> b;
  ASSERT_TRUE(encode_robot(three_waypoints(), b));
  NavCommand c;
  for (const std::size_t cut : {std::size_t{0}, std::size_t{4}, std::size_t{8}, b.size() / 2, b.size() - 1})
    EXPECT_EQ(decode_robot(b.data(), static_cast<int>(cut), c), RobotDecoded::kUndecodable) << cut;
  // One byte too many is not the message either.
  std::vector<uint8_t> longer = b;
  longer.push_back(0);
  EXPECT_EQ(decode_robot(longer.data(), static_cast<int>(longer.size()), c), RobotDecoded::kUndecodable);
  // A command's bytes read as a pose or a status (another fingerprint).
  RobotPose p;
  NavStatus s;
  EXPECT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), p), RobotDecoded::kUndecodable);
  EXPECT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), s), RobotDecoded::kUndecodable);
  ASSERT_TRUE(encode_robot(a_pose(), b));
  EXPECT_EQ(decode_robot(b.data(), static_cast<int>(b.size() - 3), p), RobotDecoded::kUndecodable);
  ASSERT_TRUE(encode_robot(a_status(), b));
  EXPECT_EQ(decode_robot(b.data(), static_cast<int>(b.size() - 9), s), RobotDecoded::kUndecodable);
  // A negative count (int16) in a status: undecodable, never an exception.
  gather_lcm::nav_status_t w = wire_status(0);
  std::vector<uint8_t> neg = encoded(w);
  // The count follows the hash (8), schema, agent (2 + 2), tick, stamp (8 + 8), command (4), state (1).
  const std::size_t at = 8 + 2 + 2 + 8 + 8 + 4 + 1;
  ASSERT_EQ(neg[at], 0);
  ASSERT_EQ(neg[at + 1], 0);
  neg[at] = 0xff, neg[at + 1] = 0xf0;
  EXPECT_EQ(decode_robot(neg.data(), static_cast<int>(neg.size()), s), RobotDecoded::kUndecodable);
}

TEST(LcmRobotCodec, AnotherSchemaVersionIsWrongVersion) {
  gather_lcm::nav_command_t c = wire_go();
  ASSERT_EQ(decode_wire<NavCommand>(c), RobotDecoded::kOk);
  c.schema_version = gather_lcm::nav_command_t::SCHEMA_VERSION + 1;
  EXPECT_EQ(decode_wire<NavCommand>(c), RobotDecoded::kWrongVersion);
  c.schema_version = 0;
  EXPECT_EQ(decode_wire<NavCommand>(c), RobotDecoded::kWrongVersion);
  gather_lcm::robot_pose_t p = wire_pose();
  ASSERT_EQ(decode_wire<RobotPose>(p), RobotDecoded::kOk);
  p.schema_version = 2;
  EXPECT_EQ(decode_wire<RobotPose>(p), RobotDecoded::kWrongVersion);
  gather_lcm::nav_status_t s = wire_status();
  ASSERT_EQ(decode_wire<NavStatus>(s), RobotDecoded::kOk);
  s.schema_version = -1;
  EXPECT_EQ(decode_wire<NavStatus>(s), RobotDecoded::kWrongVersion);
}

TEST(LcmRobotCodec, CommandsOutOfRangeAreRefused) {
  ASSERT_EQ(decode_wire<NavCommand>(wire_go()), RobotDecoded::kOk);
  auto refused = [](gather_lcm::nav_command_t w) { return decode_wire<NavCommand>(w) == RobotDecoded::kOutOfRange; };
  gather_lcm::nav_command_t w = wire_go();
  w.agent = -1;
  EXPECT_TRUE(refused(w));
  w.agent = kMaxTeam;
  EXPECT_TRUE(refused(w));
  w.agent = kMaxTeam - 1;
  EXPECT_FALSE(refused(w));
  w = wire_go(), w.command = 0;  // ids start at 1
  EXPECT_TRUE(refused(w));
  w.command = -3;
  EXPECT_TRUE(refused(w));
  w = wire_go(), w.kind = 0;
  EXPECT_TRUE(refused(w));
  w.kind = 3;
  EXPECT_TRUE(refused(w));
  // GO: 1..256 waypoints; STOP: none.
  w = wire_go(0);
  EXPECT_TRUE(refused(w));
  w = wire_go(kMaxNavWaypoints + 1);
  EXPECT_TRUE(refused(w));
  w = wire_go(kMaxNavWaypoints);
  EXPECT_FALSE(refused(w));
  w = wire_go(1), w.kind = gather_lcm::nav_command_t::STOP;
  EXPECT_TRUE(refused(w));
  w = wire_go(0), w.kind = gather_lcm::nav_command_t::STOP;
  EXPECT_FALSE(refused(w));
  // Waypoints: finite, planned times in [0, 1e9] s, tolerances in (0, 1e3] m; each waypoint checked.
  for (int i = 0; i < 2; ++i) {
    w = wire_go(), w.x[i] = kNaN;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.y[i] = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.after[i] = -0.5;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.after[i] = kNaN;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.after[i] = 2e9;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.tolerance[i] = 0.0;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.tolerance[i] = -0.25;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.tolerance[i] = kNaN;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.tolerance[i] = 1000.5;
    EXPECT_TRUE(refused(w)) << i;
    w = wire_go(), w.tolerance[i] = 1000.0;  // the bound itself
    EXPECT_FALSE(refused(w)) << i;
  }
}

TEST(LcmRobotCodec, StatusesAndPosesOutOfRangeAreRefused) {
  auto status = [](gather_lcm::nav_status_t w) { return decode_wire<NavStatus>(w); };
  gather_lcm::nav_status_t w = wire_status();
  ASSERT_EQ(status(w), RobotDecoded::kOk);
  w.agent = -2;
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(), w.agent = kMaxTeam;
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(), w.command = -1;
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(), w.command = 0;  // none received yet: fine
  EXPECT_EQ(status(w), RobotDecoded::kOk);
  w = wire_status(), w.state = gather_lcm::nav_status_t::BLOCKED + 1;
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(), w.state = -1;
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(), w.contacts = -1;
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(kMaxNavWaypoints + 1);
  EXPECT_EQ(status(w), RobotDecoded::kOutOfRange);
  w = wire_status(kMaxNavWaypoints);
  EXPECT_EQ(status(w), RobotDecoded::kOk);

  gather_lcm::robot_pose_t p = wire_pose();
  p.agent = -1;
  EXPECT_EQ(decode_wire<RobotPose>(p), RobotDecoded::kOutOfRange);
  p.agent = kMaxTeam;
  EXPECT_EQ(decode_wire<RobotPose>(p), RobotDecoded::kOutOfRange);
}

TEST(LcmRobotCodec, APoseThatIsNotANumberDecodesForTheAgentToJudge) {
  RobotPose p = a_pose();
  p.at.x = kNaN, p.heading = std::numeric_limits<double>::infinity(), p.sigma = kNaN;
  std::vector<uint8_t> b;
  ASSERT_TRUE(encode_robot(p, b));
  RobotPose got;
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), got), RobotDecoded::kOk);
  EXPECT_TRUE(std::isnan(got.at.x));
  EXPECT_EQ(got.at.y, 17.75);
  EXPECT_TRUE(std::isinf(got.heading));
  EXPECT_TRUE(std::isnan(got.sigma));
  // A status's times are the robot's too: left for RobotBase.
  NavStatus s = a_status();
  s.stamp = kNaN, s.reached_at[1] = -5.0, s.eta = kNaN;
  ASSERT_TRUE(encode_robot(s, b));
  NavStatus gs;
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), gs), RobotDecoded::kOk);
  EXPECT_TRUE(std::isnan(gs.stamp));
  EXPECT_EQ(gs.reached_at[1], -5.0);
}

// A status decoded after one refused for its count: the generated decoder
// keeps an array's old elements when the new count is 0, so the 300 times
// of the refused status are still in the wire object when a good status
// with none comes.
TEST(LcmRobotCodec, AStatusWithNoWaypointsAfterOneWithTooManyStaysInsideItsStruct) {
  const std::vector<uint8_t> bad = encoded(wire_status(300));
  const std::vector<uint8_t> good = encoded(wire_status(0));
  struct Guarded {
    NavStatus status;
    double guard[64];
  };
  auto g = std::make_unique<Guarded>();
  for (double& x : g->guard) x = -7.0;
  ASSERT_EQ(decode_robot(bad.data(), static_cast<int>(bad.size()), g->status), RobotDecoded::kOutOfRange);
  ASSERT_EQ(decode_robot(good.data(), static_cast<int>(good.size()), g->status), RobotDecoded::kOk);
  EXPECT_EQ(g->status.reached, 0u);
  int overwritten = 0;
  for (const double x : g->guard) overwritten += x != -7.0;
  // The decoder keeps the refused status's 300 waypoints in its wire object
  // for a count of 0: copying more than the count wrote past the struct (a
  // heap overflow by any robot or keyholder that sends such a pair).
  EXPECT_EQ(overwritten, 0) << "decode_robot wrote " << overwritten << " doubles past the NavStatus";
}

// --- The link over memq:// -------------------------------------------------

// An envelope of `payload` on `channel`, from `sender`, signed by `tx` (as
// the robot, or a forger, would).
std::vector<uint8_t> sealed(FleetAuth& tx, const std::string& channel, int16_t sender,
                            const std::vector<uint8_t>& payload) {
  gather_lcm::envelope_t e{};
  EnvelopeHead h;
  e.payload = payload;
  tx.sign(channel.c_str(), sender, e.payload.data(), e.payload.size(), h, e.mac);
  e.version = h.version, e.key_id = h.key_id, e.sender = h.sender, e.counter = h.counter;
  e.size = static_cast<int32_t>(payload.size());
  return encoded(e);
}

std::vector<std::string> channels_of(std::vector<int> ids) {
  std::vector<std::string> c;
  for (int id : ids)
    c.insert(c.end(),
             {robot_command_channel(id), robot_pose_channel(id), robot_status_channel(id), robot_scan_channel(id)});
  return c;
}

template <typename M>
std::vector<uint8_t> payload(const M& m) {
  std::vector<uint8_t> b;
  EXPECT_TRUE(encode_robot(m, b));
  return b;
}

void hand(LcmRobotLink& link, const std::string& channel, const std::vector<uint8_t>& bytes) {
  link.on_message(channel.c_str(), bytes.data(), static_cast<int>(bytes.size()));
}

TEST(LcmRobotLink, TheChannelsAreNamedAfterTheAgent) {
  EXPECT_EQ(robot_command_channel(3), "GATHER_ROBOT_CMD_3");
  EXPECT_EQ(robot_pose_channel(17), "GATHER_ROBOT_POSE_17");
  EXPECT_EQ(robot_status_channel(0), "GATHER_ROBOT_STATUS_0");
  EXPECT_EQ(robot_scan_channel(12), "GATHER_ROBOT_SCAN_12");
}

RobotScan a_scan(int16_t agent = 3, int rays = 5) {
  RobotScan s;
  s.agent = agent, s.tick = 11, s.stamp = 7.5, s.at = Point2{2.5, -1.25}, s.heading = 0.75;
  s.angle_min = -1.5f, s.angle_increment = 0.75f, s.range_max = 5.0f;
  s.rays = static_cast<uint16_t>(rays);
  for (int k = 0; k < rays; ++k) s.ranges[k] = 0.5f * static_cast<float>(k + 1);
  s.ranges[rays - 1] = std::numeric_limits<float>::infinity();  // nothing within range
  return s;
}

TEST(LcmRobotCodec, AScanSurvivesTheRoundTripAndBadOnesAreRefused) {
  std::vector<uint8_t> b;
  ASSERT_TRUE(encode_robot(a_scan(), b));
  RobotScan g;
  ASSERT_EQ(decode_robot(b.data(), static_cast<int>(b.size()), g), RobotDecoded::kOk);
  EXPECT_EQ(g.agent, 3);
  EXPECT_EQ(g.tick, 11);
  EXPECT_EQ(g.stamp, 7.5);
  EXPECT_EQ(g.at.x, 2.5);
  EXPECT_EQ(g.at.y, -1.25);
  EXPECT_EQ(g.heading, 0.75);
  EXPECT_EQ(g.angle_min, -1.5f);
  EXPECT_EQ(g.angle_increment, 0.75f);
  EXPECT_EQ(g.range_max, 5.0f);
  ASSERT_EQ(g.rays, 5u);
  EXPECT_EQ(g.ranges[0], 0.5f);
  EXPECT_EQ(g.ranges[3], 2.0f);
  EXPECT_TRUE(std::isinf(g.ranges[4]));
  // The largest scan fits the link's buffer; one more ray does not encode.
  ASSERT_TRUE(encode_robot(a_scan(3, kMaxScanRays), b));
  EXPECT_LT(b.size(), 16384u - 200u);
  RobotScan too_many = a_scan();
  too_many.rays = kMaxScanRays + 1;
  EXPECT_FALSE(encode_robot(too_many, b));
  // No rays, a pose that is not a number, no range: refused.
  gather_lcm::robot_scan_t w{};
  w.schema_version = gather_lcm::robot_scan_t::SCHEMA_VERSION;
  w.agent = 3, w.x = 1.0, w.y = 2.0, w.theta = 0.0, w.angle_min = -1.0f, w.angle_increment = 0.5f;
  w.range_max = 4.0f, w.rays = 2, w.ranges = {1.0f, 2.0f};
  EXPECT_EQ(decode_wire<RobotScan>(w), RobotDecoded::kOk);
  gather_lcm::robot_scan_t none = w;
  none.rays = 0, none.ranges.clear();
  EXPECT_EQ(decode_wire<RobotScan>(none), RobotDecoded::kOutOfRange);
  gather_lcm::robot_scan_t nan = w;
  nan.x = kNaN;
  EXPECT_EQ(decode_wire<RobotScan>(nan), RobotDecoded::kOutOfRange);
  gather_lcm::robot_scan_t blind = w;
  blind.range_max = 0.0f;
  EXPECT_EQ(decode_wire<RobotScan>(blind), RobotDecoded::kOutOfRange);
  gather_lcm::robot_scan_t old = w;
  old.schema_version = 2;
  EXPECT_EQ(decode_wire<RobotScan>(old), RobotDecoded::kWrongVersion);
}

TEST(LcmRobotLink, AViewerTakesEachRobotsSignedScansOnly) {
  const FleetKey key = test_key();
  LcmRobotLink viewer("memq://", LcmRobotLink::Side::kViewer, {0, 1, 2, 3}, key);
  FleetAuth robots(key, channels_of({0, 1, 2, 3}), kMaxTeam + 1);
  const std::string scan_3 = robot_scan_channel(3);
  hand(viewer, scan_3, sealed(robots, scan_3, 3, payload(a_scan(3))));
  ASSERT_EQ(viewer.scans().size(), 1u);
  EXPECT_EQ(viewer.scans()[0].rays, 5u);
  hand(viewer, scan_3, sealed(robots, scan_3, 2, payload(a_scan(3))));  // another robot's signature
  hand(viewer, scan_3, sealed(robots, scan_3, 3, payload(a_scan(2))));  // another robot inside
  EXPECT_EQ(viewer.rejected().wrong_sender, 2);
  // Poses and statuses are not a viewer's: it does not even listen.
  EXPECT_FALSE(viewer.publish(a_scan(3)));
  EXPECT_EQ(viewer.scans().size(), 1u);
  // The robots' side publishes scans of its own robots only.
  LcmRobotLink world("memq://", LcmRobotLink::Side::kRobots, {0, 3}, key);
  EXPECT_TRUE(world.publish(a_scan(3)));
  EXPECT_FALSE(world.publish(a_scan(1)));
}

TEST(LcmRobotLink, AnAgentTakesItsRobotsSignedReportsAndRefusesWrongSendersAndReplays) {
  const FleetKey key = test_key();
  LcmRobotLink link("memq://", LcmRobotLink::Side::kAgent, {3}, key);
  FleetAuth robot(key, channels_of({3, 4, 5}), kMaxTeam + 1);
  const std::string pose_3 = robot_pose_channel(3), status_3 = robot_status_channel(3);

  const std::vector<uint8_t> good = sealed(robot, pose_3, 3, payload(a_pose(3)));
  hand(link, pose_3, good);
  ASSERT_EQ(link.poses().size(), 1u);
  EXPECT_EQ(link.poses()[0].at.x, 5.5);
  EXPECT_EQ(link.poses()[0].stamp, 1234.5);
  // The same bytes again: a replay.
  hand(link, pose_3, good);
  EXPECT_EQ(link.rejected().replayed, 1);
  EXPECT_EQ(link.poses().size(), 1u);
  // Signed with the key, by agent 4, on agent 3's channel: the MAC holds,
  // the sender is not the channel's.
  hand(link, pose_3, sealed(robot, pose_3, 4, payload(a_pose(3))));
  EXPECT_EQ(link.rejected().wrong_sender, 1);
  // Signed by 3 but naming agent 4 inside.
  hand(link, pose_3, sealed(robot, pose_3, 3, payload(a_pose(4))));
  EXPECT_EQ(link.rejected().wrong_sender, 2);
  EXPECT_EQ(link.poses().size(), 1u);

  // A status, signed by its robot: taken with its waypoint times.
  hand(link, status_3, sealed(robot, status_3, 3, payload(a_status(3))));
  ASSERT_EQ(link.statuses().size(), 1u);
  EXPECT_EQ(link.statuses()[0].state, NavState::kFailed);
  EXPECT_EQ(link.statuses()[0].reached, 2u);
  EXPECT_EQ(link.statuses()[0].reached_at[1], 45.5);
  hand(link, status_3, sealed(robot, status_3, 5, payload(a_status(3))));  // another sender
  EXPECT_EQ(link.rejected().wrong_sender, 3);
  hand(link, status_3, sealed(robot, status_3, 3, payload(a_status(5))));  // another agent inside
  EXPECT_EQ(link.rejected().wrong_sender, 4);
  EXPECT_EQ(link.statuses().size(), 1u);

  // Signed with another key of the same id, unsigned, changed on the way.
  FleetAuth forger(test_key(7, 0x11), channels_of({3}), kMaxTeam + 1);
  hand(link, pose_3, sealed(forger, pose_3, 3, payload(a_pose(3))));
  EXPECT_EQ(link.rejected().bad_mac, 1);
  FleetAuth insecure(std::nullopt, channels_of({3}), kMaxTeam + 1);
  hand(link, pose_3, sealed(insecure, pose_3, 3, payload(a_pose(3))));
  EXPECT_EQ(link.rejected().unsigned_msgs, 1);
  std::vector<uint8_t> changed = sealed(robot, pose_3, 3, payload(a_pose(3)));
  changed[changed.size() - 40] ^= 0x01;  // a byte of the payload (the MAC is the last 32)
  hand(link, pose_3, changed);
  EXPECT_EQ(link.rejected().bad_mac, 2);
  EXPECT_EQ(link.poses().size(), 1u);

  // Signed right, but not the channel's type, or of another schema version:
  // counted by the transport.
  hand(link, status_3, sealed(robot, status_3, 3, payload(a_pose(3))));
  EXPECT_EQ(link.refused().undecodable, 1);
  gather_lcm::robot_pose_t old = wire_pose();
  old.schema_version = 2;
  hand(link, pose_3, sealed(robot, pose_3, 3, encoded(old)));
  EXPECT_EQ(link.refused().wrong_version, 1);
  gather_lcm::nav_status_t bad_state = wire_status();
  bad_state.state = 9;
  hand(link, status_3, sealed(robot, status_3, 3, encoded(bad_state)));
  EXPECT_EQ(link.refused().out_of_range, 1);
  EXPECT_EQ(link.statuses().size(), 1u);

  // A pose that is not a number is its robot's business: it arrives.
  RobotPose nan_pose = a_pose(3);
  nan_pose.at.x = kNaN;
  hand(link, pose_3, sealed(robot, pose_3, 3, payload(nan_pose)));
  ASSERT_EQ(link.poses().size(), 2u);
  EXPECT_TRUE(std::isnan(link.poses()[1].at.x));
  // Replayed 1, wrong sender 4, bad MAC 2, unsigned 1.
  EXPECT_EQ(link.rejected().total(), 8);
}

TEST(LcmRobotLink, TheRobotsSideTakesEachAgentsSignedCommands) {
  const FleetKey key = test_key();
  LcmRobotLink world("memq://", LcmRobotLink::Side::kRobots, {0, 3}, key);
  FleetAuth agents(key, channels_of({0, 3}), kMaxTeam + 1);
  const std::string cmd_0 = robot_command_channel(0), cmd_3 = robot_command_channel(3);
  NavCommand c = three_waypoints();
  c.agent = 3;
  const std::vector<uint8_t> good = sealed(agents, cmd_3, 3, payload(c));
  hand(world, cmd_3, good);
  ASSERT_EQ(world.commands().size(), 1u);
  const NavCommand& got = world.commands()[0];
  EXPECT_EQ(got.agent, 3);
  ASSERT_EQ(got.n, 3u);
  EXPECT_EQ(got.tolerance[0], 0.25);
  EXPECT_EQ(got.tolerance[1], 1.0);
  EXPECT_EQ(got.tolerance[2], 0.1);
  EXPECT_EQ(got.points[2].x, 19.05);
  hand(world, cmd_3, good);  // replayed
  EXPECT_EQ(world.rejected().replayed, 1);
  // Agent 0 (a keyholder) commanding agent 3's robot.
  hand(world, cmd_3, sealed(agents, cmd_3, 0, payload(c)));
  EXPECT_EQ(world.rejected().wrong_sender, 1);
  // A command naming agent 0 on agent 3's channel.
  c.agent = 0;
  hand(world, cmd_3, sealed(agents, cmd_3, 0, payload(c)));
  hand(world, cmd_3, sealed(agents, cmd_3, 3, payload(c)));
  EXPECT_EQ(world.rejected().wrong_sender, 3);
  EXPECT_EQ(world.commands().size(), 1u);
  // Agent 0's own command on its own channel.
  hand(world, cmd_0, sealed(agents, cmd_0, 0, payload(c)));
  ASSERT_EQ(world.commands().size(), 2u);
  EXPECT_EQ(world.commands()[1].agent, 0);
  // A command with a waypoint of tolerance 0 is out of range.
  gather_lcm::nav_command_t zero = wire_go();
  zero.tolerance[1] = 0.0;
  hand(world, cmd_3, sealed(agents, cmd_3, 3, encoded(zero)));
  EXPECT_EQ(world.refused().out_of_range, 1);
  EXPECT_EQ(world.commands().size(), 2u);
}

TEST(LcmRobotLink, AnInsecureLinkTakesUnsignedMessages) {
  LcmRobotLink link("memq://", LcmRobotLink::Side::kAgent, {2}, std::nullopt);
  FleetAuth insecure(std::nullopt, channels_of({2}), kMaxTeam + 1);
  const std::string pose_2 = robot_pose_channel(2);
  hand(link, pose_2, sealed(insecure, pose_2, 2, payload(a_pose(2))));
  ASSERT_EQ(link.poses().size(), 1u);
  // The agent still checks who it is from.
  hand(link, pose_2, sealed(insecure, pose_2, 1, payload(a_pose(2))));
  EXPECT_EQ(link.rejected().wrong_sender, 1);
  EXPECT_EQ(link.poses().size(), 1u);
}

TEST(LcmRobotLink, EachSidePublishesOnlyWhatItSendsAndOnlyForItsAgents) {
  const FleetKey key = test_key();
  LcmRobotLink agent("memq://", LcmRobotLink::Side::kAgent, {3}, key);
  NavCommand c = three_waypoints();
  c.agent = 3;
  agent.send(c);
  EXPECT_EQ(agent.sent(), 1);
  EXPECT_EQ(agent.publish_failures(), 0);
  c.agent = 4;  // not this link's agent
  agent.send(c);
  c.agent = 3, c.n = kMaxNavWaypoints + 1;  // does not encode
  agent.send(c);
  EXPECT_FALSE(agent.publish(a_pose(3)));  // an agent does not report poses
  EXPECT_FALSE(agent.publish(a_status(3)));
  EXPECT_EQ(agent.sent(), 1);
  EXPECT_EQ(agent.publish_failures(), 4);
  // It hears nothing of its own command (memq: its own queue; it does not
  // take commands).
  agent.handle(20);
  EXPECT_TRUE(agent.poses().empty());
  EXPECT_TRUE(agent.statuses().empty());
  EXPECT_TRUE(agent.commands().empty());

  LcmRobotLink world("memq://", LcmRobotLink::Side::kRobots, {0, 3}, key);
  EXPECT_TRUE(world.publish(a_pose(3)));
  EXPECT_TRUE(world.publish(a_status(0)));
  EXPECT_FALSE(world.publish(a_pose(4)));  // no robot of its
  c.agent = 3, c.n = 3;
  world.send(c);  // robots do not command
  EXPECT_EQ(world.sent(), 2);
  EXPECT_EQ(world.publish_failures(), 2);
}

TEST(LcmRobotLink, AUrlLcmCannotOpenIsAnErrorNamingTheFlag) {
  try {
    LcmRobotLink link("nosuchprovider://x", LcmRobotLink::Side::kAgent, {0}, std::nullopt);
    FAIL() << "opened nosuchprovider://x";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--robot-url"), std::string::npos) << e.what();
  }
}

// Two links (an agent and its robot) through UDP multicast: only inside a
// private network namespace (tools/netns-run sets GATHER_NETNS=1), never on
// the host's network.
TEST(LcmRobotLink, AnAgentAndItsRobotOverUdpmInsideANetworkNamespace) {
  const char* netns = std::getenv("GATHER_NETNS");
  if (!netns || std::string(netns) != "1") GTEST_SKIP() << "run inside tools/netns-run";
  const std::string url = "udpm://239.255.76.67:7671?ttl=0";
  const FleetKey key = test_key();
  LcmRobotLink agent(url, LcmRobotLink::Side::kAgent, {3}, key);
  LcmRobotLink robot(url, LcmRobotLink::Side::kRobots, {3}, key);
  NavCommand c = three_waypoints();
  c.agent = 3;
  agent.send(c);
  for (int i = 0; i < 100 && robot.commands().empty(); ++i) robot.handle(20);
  ASSERT_EQ(robot.commands().size(), 1u);
  EXPECT_EQ(robot.commands()[0].id, 7);
  EXPECT_EQ(robot.commands()[0].tolerance[1], 1.0);
  EXPECT_TRUE(robot.publish(a_pose(3)));
  EXPECT_TRUE(robot.publish(a_status(3)));
  for (int i = 0; i < 100 && (agent.poses().empty() || agent.statuses().empty()); ++i) agent.handle(20);
  ASSERT_EQ(agent.poses().size(), 1u);
  ASSERT_EQ(agent.statuses().size(), 1u);
  EXPECT_EQ(agent.poses()[0].at.y, 17.75);
  EXPECT_EQ(agent.statuses()[0].reached_at[0], 40.25);
  EXPECT_EQ(agent.rejected().total(), 0);
  EXPECT_EQ(robot.rejected().total(), 0);
}

}  // namespace
}  // namespace agent
}  // namespace gather
