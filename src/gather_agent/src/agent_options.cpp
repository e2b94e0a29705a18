#include "gather_agent/agent_options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "gather_core/error.hpp"
#include "gather_core/input_ranges.hpp"

namespace gather {
namespace {

const char* kWhere = "gather_agent";

double parse_number(const std::string& flag, const char* s) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s, &end);
  if (*s == '\0' || *end != '\0' || errno != 0 || !std::isfinite(v))
    throw Error(kWhere, flag + " expects a number, got '" + std::string(s).substr(0, 40) + "'");
  return v;
}

// The value of the flag of range `id` (gather_core/input_ranges.hpp).
double ranged(range::Id id, const char* s) {
  const InputRange& r = input_range(id);
  const double v = parse_number(r.key, s);
  if (!r.accepts(v))
    throw Error(kWhere,
                std::string(r.key) + " must be in " + r.text() + ", got '" + std::string(s).substr(0, 40) + "'");
  return v;
}

}  // namespace

const char* agent_usage() {
  return "usage: gather_agent --id K --plan PLAN_DIR (--key-file F | --insecure) [--lcm-url URL] [--reply-url URL] "
         "[--motion sim|lcm [--robot-url URL] [--robot-silence S] [--waypoint-tolerance M]] [--silence S] "
         "[--journal DIR [--rejoin]] [--clock-skew S]";
}

AgentOptions parse_agent_options(int argc, char** argv) {
  AgentOptions o;
  bool have_id = false, silence_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const std::string& flag) -> const char* {
      if (i + 1 >= argc) throw Error(kWhere, flag + " needs a value");
      return argv[++i];
    };
    if (a.find(":=") != std::string::npos) continue;  // a ROS remapping (roslaunch adds __name:=, __log:=)
    if (a == "--help" || a == "-h") {
      o.help = true;
      return o;
    } else if (a == "--id") {
      o.id = static_cast<int>(ranged(range::kAgentId, value(a)));
      have_id = true;
    } else if (a == "--plan") {
      o.plan = value(a);
    } else if (a == "--lcm-url") {
      o.lcm_url = value(a);
    } else if (a == "--reply-url") {
      o.reply_url = value(a);
    } else if (a == "--motion") {
      o.motion = value(a);
      if (o.motion != "sim" && o.motion != "lcm")
        throw Error(kWhere,
                    "--motion must be sim (an ideal base) or lcm (a robot behind the robot interface, "
                    "docs/robots.md), got '" +
                        o.motion.substr(0, 40) + "'");
    } else if (a == "--robot-url") {
      o.robot_url = value(a);
    } else if (a == "--robot-silence") {
      o.robot_silence_s = ranged(range::kAgentRobotSilence, value(a));
    } else if (a == "--waypoint-tolerance") {
      o.tolerance_m = ranged(range::kAgentTolerance, value(a));
    } else if (a == "--journal") {
      o.journal = value(a);
      if (o.journal.empty()) throw Error(kWhere, "--journal needs a directory");
    } else if (a == "--key-file") {
      o.key_file = value(a);
      if (o.key_file.empty()) throw Error(kWhere, "--key-file needs a file");
    } else if (a == "--insecure") {
      o.insecure = true;
    } else if (a == "--rejoin") {
      o.rejoin = true;
    } else if (a == "--clock-skew") {
      o.clock_skew_s = ranged(range::kAgentClockSkew, value(a));
    } else if (a == "--silence") {
      o.silence_s = ranged(range::kAgentSilence, value(a));
      silence_given = true;
    } else {
      throw Error(kWhere, "unexpected argument '" + a.substr(0, 60) + "' (" + agent_usage() + ")");
    }
  }
  // On a robot the radio may be gone for minutes (out of range, a
  // partition): the agent keeps what it carries and waits far longer than a
  // simulation's process would.
  if (!silence_given && o.motion == "lcm") o.silence_s = kRobotSilence_s;
  if (!have_id) throw Error(kWhere, std::string("--id is required (") + agent_usage() + ")");
  if (o.plan.empty()) throw Error(kWhere, std::string("--plan is required (") + agent_usage() + ")");
  if (o.rejoin && o.journal.empty()) throw Error(kWhere, "--rejoin needs --journal (the journal it replays)");
  if (o.motion != "lcm" && (!o.robot_url.empty())) throw Error(kWhere, "--robot-url needs --motion lcm");
  return o;
}

}  // namespace gather
