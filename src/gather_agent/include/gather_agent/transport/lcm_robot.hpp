#pragma once
// The robot interface over LCM (docs/robots.md): an agent's navigation
// commands to its robot and the robot's poses and statuses back, on channels
// named after the agent id (GATHER_ROBOT_CMD_<id>, GATHER_ROBOT_POSE_<id>,
// GATHER_ROBOT_STATUS_<id>; GATHER_ROBOT_SCAN_<id> for views), each message in a signed envelope like every
// fleet message, its sender the agent's id. The only code that sees the
// generated robot_pose_t, nav_command_t, nav_status_t and robot_scan_t: it converts them
// at this edge, and counts and drops what does not decode, carries another
// schema version, or names another agent than its channel. The same
// conversions serve gather run's pipe to gather_world (encode_robot,
// decode_robot: no envelope, a parent and its child).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gather_agent/motion/robot_interface.hpp"
#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"

typedef struct _lcm_t lcm_t;

namespace gather {
namespace agent {

class Envelopes;

// The LCM encoding of a message (its type's fingerprint first) into `out`
// (resized to fit); false when it does not encode (a count out of range).
bool encode_robot(const NavCommand& m, std::vector<uint8_t>& out);
bool encode_robot(const RobotPose& m, std::vector<uint8_t>& out);
bool encode_robot(const NavStatus& m, std::vector<uint8_t>& out);
bool encode_robot(const RobotScan& m, std::vector<uint8_t>& out);
enum class RobotDecoded : uint8_t { kOk, kUndecodable, kWrongVersion, kOutOfRange };
// Decodes and checks the fields a receiver relies on (counts, states, the
// kind of command, finite waypoints); the values a robot reports are left
// for the agent's RobotBase to judge (a NaN pose is its robot's fault, not
// the transport's).
RobotDecoded decode_robot(const void* data, int size, NavCommand& out);
RobotDecoded decode_robot(const void* data, int size, RobotPose& out);
RobotDecoded decode_robot(const void* data, int size, NavStatus& out);
RobotDecoded decode_robot(const void* data, int size, RobotScan& out);

class LcmRobotLink : public NavCommandSink {
 public:
  enum class Side : uint8_t {
    kAgent,   // agent ids[0]: sends commands, takes its robot's poses and statuses
    kRobots,  // the robots of agents `ids` (gather_world, a driver): take commands, send poses, statuses, scans
    kViewer,  // a view of the robots of agents `ids` (fleet_node with laser:=true): takes their scans
  };
  // Opens `url`; `key`: the fleet key (empty: unsigned, insecure). Throws
  // gather::Error("--robot-url", ...) naming the URL when LCM cannot open it.
  LcmRobotLink(const std::string& url, Side side, std::vector<int> ids, std::optional<FleetKey> key);
  // The same on an LCM instance that is already open (the fleet's, when the
  // robot interface shares its URL: one socket less on a small robot); it
  // must outlive the link, and whoever handles it dispatches this link's
  // messages too.
  LcmRobotLink(lcm_t* shared, Side side, std::vector<int> ids, std::optional<FleetKey> key);
  ~LcmRobotLink() override;
  LcmRobotLink(const LcmRobotLink&) = delete;
  LcmRobotLink& operator=(const LcmRobotLink&) = delete;

  void send(const NavCommand& command) override;  // kAgent
  bool publish(const RobotPose& pose);            // kRobots
  bool publish(const NavStatus& status);          // kRobots
  bool publish(const RobotScan& scan);            // kRobots

  // Dispatches what arrived, waiting up to `timeout_ms`; false when nothing came.
  bool handle(int timeout_ms);
  int fileno() const;

  // What arrived, in arrival order; the caller takes and clears.
  std::vector<RobotPose>& poses() { return poses_; }
  std::vector<NavStatus>& statuses() { return statuses_; }
  std::vector<NavCommand>& commands() { return commands_; }
  std::vector<RobotScan>& scans() { return scans_; }  // kViewer (reserved: at most 4 per robot held)
  const TransportCounters& refused() const { return refused_; }
  const AuthCounters& rejected() const { return auth_.counters(); }
  int64_t sent() const { return sent_; }
  int64_t publish_failures() const { return publish_failures_; }

  void on_message(const char* channel, const void* data, int size);  // LCM's handler (public for the C callback)

 private:
  bool seal_and_publish(const std::string& channel, int16_t sender);
  int id_index(int agent) const;  // index of `agent` in ids_, -1 when not one of them

  void subscribe();

  lcm_t* lcm_ = nullptr;
  bool owned_ = true;
  Side side_;
  std::vector<int> ids_;
  std::vector<std::string> command_channels_, pose_channels_, status_channels_, scan_channels_;
  FleetAuth auth_;
  std::unique_ptr<Envelopes> envelopes_;
  std::vector<uint8_t> buffer_;
  std::vector<RobotPose> poses_;
  std::vector<NavStatus> statuses_;
  std::vector<NavCommand> commands_;
  std::vector<RobotScan> scans_;
  TransportCounters refused_;
  int64_t sent_ = 0, publish_failures_ = 0;
};

}  // namespace agent
}  // namespace gather
