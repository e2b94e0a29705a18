// The plan digest both sides of the lockstep compare before a mission
// (plan_digest); the two sides are lockstep_agent.cpp and lockstep_master.cpp.
#include "gather_agent/runner/lockstep.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

void fnv1a(uint64_t& h, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot read (needed for the plan's digest)");
  char buf[65536];
  while (in) {
    in.read(buf, sizeof buf);
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ static_cast<uint8_t>(buf[i])) * 1099511628211ull;
  }
}

}  // namespace

uint64_t plan_digest(const LoadedPlan& p) {
  namespace fs = std::filesystem;
  const fs::path yaml = fs::is_directory(p.dir) ? fs::path(p.dir) / "plan.yaml" : fs::path(p.dir);
  uint64_t h = 14695981039346656037ull;
  fnv1a(h, yaml.string());
  fnv1a(h, (yaml.parent_path() / p.plan.file.labels_png).string());
  fnv1a(h, p.scenario.path);
  fnv1a(h, p.scenario.map_path);
  fnv1a(h, p.scenario.map_meta.image);
  return h;
}

}  // namespace agent
}  // namespace gather
