#include "gather_agent/runner/agent_keys.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "gather_agent/roles/role.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {

namespace {

std::string ids_text(const std::vector<int16_t>& ids) {
  std::string s;
  for (int16_t id : ids) s += (s.empty() ? "" : ", ") + (id < 0 ? std::string("the OC") : std::to_string(id));
  return s.empty() ? "none" : s;
}

}  // namespace

KeyRing agent_keys_for(const FleetKey& master, int agent, const plan::PlanFile& plan) {
  return agent_key_ring(master, static_cast<int16_t>(agent), plan_links(plan).peers(static_cast<int16_t>(agent)));
}

std::string master_warning(const std::string& path, int id) {
  return "WARNING: " + path +
         " is the fleet's master key: whoever takes this robot can sign as any agent and as the OC; give it its own "
         "(gather keygen FILE --agent " +
         std::to_string(id) + " --plan PLAN_DIR --master MASTER; docs/security.md)";
}

void check_agent_keys(const KeyRing& keys, const std::string& path, int id, const plan::PlanFile& plan) {
  if (keys.master()) return;
  if (keys.agent != id)
    throw Error(path, "agent " + std::to_string(keys.agent) + "'s key file, given to agent " + std::to_string(id));
  std::vector<int16_t> plan_peers = plan_links(plan).peers(static_cast<int16_t>(id)), file_peers;
  for (const auto& l : keys.links) file_peers.push_back(l.first);
  std::sort(plan_peers.begin(), plan_peers.end());
  if (plan_peers != file_peers)
    throw Error(path + ": link", "agent " + std::to_string(id) + "'s keys are for links to " + ids_text(file_peers) +
                                     ", its plan links it to " + ids_text(plan_peers) +
                                     ": make its key file from this plan (gather keygen FILE --agent " +
                                     std::to_string(id) + " --plan PLAN_DIR --master MASTER)");
}

std::vector<std::string> write_agent_keys(const FleetKey& master, const plan::PlanFile& plan, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || ::chmod(dir.c_str(), 0700) != 0)
    throw Error(dir, "cannot make the agents' key directory: " + (ec ? ec.message() : std::strerror(errno)));
  const FleetLinks links = plan_links(plan);
  std::vector<std::string> paths;
  for (int a = 0; a < links.agents(); ++a) {
    const std::string path = dir + "/agent-" + std::to_string(a) + ".key";
    std::filesystem::remove(path, ec);
    write_key_ring(path, agent_key_ring(master, static_cast<int16_t>(a), links.peers(static_cast<int16_t>(a))));
    paths.push_back(path);
  }
  return paths;
}

}  // namespace agent
}  // namespace gather
