#pragma once
// Command line of the gather_agent binary.
#include <string>

namespace gather {

// How long an agent on a robot (--motion lcm) waits for the OC by default [s].
constexpr double kRobotSilence_s = 600.0;

struct AgentOptions {
  int id = -1;                   // --id K, 0 <= K < N
  std::string plan;              // --plan PLAN_DIR (a `gather plan` output: plan.yaml, labels.png)
  std::string lcm_url;           // --lcm-url URL; empty = LCM_DEFAULT_URL or LCM's default
  std::string reply_url;         // --reply-url URL; empty = the LCM URL's port + 1 (lockstep replies)
  std::string motion = "sim";    // --motion sim|lcm: an ideal base, or a robot behind the robot interface
  std::string robot_url;         // --robot-url URL: the robot interface's LCM URL; empty = the fleet's
  double robot_silence_s = 2.0;  // --robot-silence S: RobotBaseParams::silence_s
  double tolerance_m = 0.25;     // --waypoint-tolerance M: RobotBaseParams::tolerance_m
  double silence_s = 30.0;    // --silence S: stop when the OC is silent this long (kRobotSilence_s with --motion lcm)
  std::string journal;        // --journal DIR: keep what it carries in DIR/agent_K.journal (docs/faults.md)
  std::string key_file;       // --key-file F: the fleet key (docs/security.md)
  bool insecure = false;      // --insecure: unsigned fleet traffic (a warning at start)
  bool rejoin = false;        // --rejoin: a restart: replay the journal, join the mission under way
  double clock_skew_s = 0.0;  // --clock-skew S: tests only: this host's clock reads S s off (docs/robots.md)
  bool help = false;          // --help: print the usage and exit 0
};

// Parses argv; throws gather::Error("gather_agent", ...) on a bad command line.
AgentOptions parse_agent_options(int argc, char** argv);

const char* agent_usage();

}  // namespace gather
