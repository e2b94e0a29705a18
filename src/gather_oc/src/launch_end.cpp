#include "gather_oc/launch_end.hpp"

#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <iterator>

namespace gather {

bool parent_is_roslaunch() {
  const pid_t parent = getppid();
  if (parent <= 1) return false;
  std::ifstream in("/proc/" + std::to_string(parent) + "/cmdline", std::ios::binary);
  const std::string cmd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return cmd.find("roslaunch") != std::string::npos;
}

bool end_launch() {
  if (!parent_is_roslaunch()) return false;
  return kill(getppid(), SIGINT) == 0;
}

}  // namespace gather
