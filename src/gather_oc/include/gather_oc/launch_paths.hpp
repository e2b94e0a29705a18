#pragma once
#include <cstdlib>
#include <string>

namespace gather {

// roslaunch starts nodes in ROS_HOME, not where the user typed the command;
// the inherited $PWD still names that directory, so relative paths given as
// launch arguments are resolved against it.
inline std::string resolve_launch_path(const std::string& path) {
  if (path.empty() || path[0] == '/') return path;
  const char* pwd = std::getenv("PWD");
  return pwd && *pwd ? std::string(pwd) + "/" + path : path;
}

}  // namespace gather
