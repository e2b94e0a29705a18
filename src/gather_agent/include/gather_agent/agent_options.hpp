#pragma once
// Command line of the gather_agent binary.
#include <string>

namespace gather {

struct AgentOptions {
  int id = -1;                 // --id K, 0 <= K < N
  std::string lcm_url;         // --lcm-url URL; empty = LCM's default (LCM_DEFAULT_URL)
  double heartbeat_hz = 2.0;   // --rate HZ, heartbeat rate
  std::string scenario;        // positional
};

// Parses argv; throws gather::Error("gather_agent", ...) on a bad command line.
AgentOptions parse_agent_options(int argc, char** argv);

const char* agent_usage();

}  // namespace gather
