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
    throw Error(kWhere, flag + " expects a number, got '" + s + "'");
  return v;
}

}  // namespace

const char* agent_usage() {
  return "usage: gather_agent --id K [--lcm-url URL] [--rate HZ] SCENARIO";
}

AgentOptions parse_agent_options(int argc, char** argv) {
  AgentOptions o;
  bool have_id = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const std::string& flag) -> const char* {
      if (i + 1 >= argc) throw Error(kWhere, flag + " needs a value");
      return argv[++i];
    };
    if (a == "--id") {
      const double v = parse_number(a, value(a));
      if (v != std::floor(v) || v < 0 || v > 1e6) throw Error(kWhere, "--id expects an integer >= 0");
      o.id = static_cast<int>(v);
      have_id = true;
    } else if (a == "--lcm-url") {
      o.lcm_url = value(a);
    } else if (a == "--rate") {
      o.heartbeat_hz = parse_number(a, value(a));
      if (!(o.heartbeat_hz > 0 && o.heartbeat_hz <= 1000)) throw Error(kWhere, "--rate must be in (0, 1000] Hz");
    } else if (a.size() > 1 && a[0] == '-') {
      throw Error(kWhere, "unknown option " + a + " (" + agent_usage() + ")");
    } else if (o.scenario.empty()) {
      o.scenario = a;
    } else {
      throw Error(kWhere, "more than one scenario given (" + std::string(agent_usage()) + ")");
    }
  }
  if (!have_id) throw Error(kWhere, std::string("--id is required (") + agent_usage() + ")");
  if (o.scenario.empty()) throw Error(kWhere, std::string("no scenario given (") + agent_usage() + ")");
  return o;
}

}  // namespace gather
