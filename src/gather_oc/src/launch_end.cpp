#include "gather_oc/launch_end.hpp"

#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <string>

namespace gather {

namespace {

// Whether process `pid` runs roslaunch: its command line's program (or, for
// a Python entry point, the script it runs) is named roslaunch.
bool is_roslaunch(pid_t pid) {
  if (pid <= 1) return false;
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline", std::ios::binary);
  std::string arg;
  for (int i = 0; i < 2 && std::getline(in, arg, '\0'); ++i) {
    const std::size_t slash = arg.rfind('/');
    if ((slash == std::string::npos ? arg : arg.substr(slash + 1)) == "roslaunch") return true;
  }
  return false;
}

}  // namespace

bool parent_is_roslaunch() { return is_roslaunch(getppid()); }

bool end_launch() {
  const pid_t parent = getppid();  // once: a parent that died meanwhile is not signalled
  return is_roslaunch(parent) && kill(parent, SIGINT) == 0;
}

}  // namespace gather
