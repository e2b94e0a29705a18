#include "gather_agent/agent_options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "gather_core/error.hpp"

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
      const double v = parse_number(a, value(a));
      if (v != std::floor(v) || v < 0 || v > 1e6) throw Error(kWhere, "--id expects an integer >= 0");
      o.id = static_cast<int>(v);
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
      o.robot_silence_s = parse_number(a, value(a));
      if (!(o.robot_silence_s >= 0.2 && o.robot_silence_s <= 600))
        throw Error(kWhere, "--robot-silence must be in [0.2, 600] s");
    } else if (a == "--waypoint-tolerance") {
      o.tolerance_m = parse_number(a, value(a));
      if (!(o.tolerance_m >= 0.01 && o.tolerance_m <= 10))
        throw Error(kWhere, "--waypoint-tolerance must be in [0.01, 10] m");
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
      o.clock_skew_s = parse_number(a, value(a));
      if (!(std::abs(o.clock_skew_s) <= 3600)) throw Error(kWhere, "--clock-skew must be in [-3600, 3600] s");
    } else if (a == "--silence") {
      o.silence_s = parse_number(a, value(a));
      silence_given = true;
      if (!(o.silence_s > 0 && o.silence_s <= 86400)) throw Error(kWhere, "--silence must be in (0, 86400] s");
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
