#pragma once
// Ending a roslaunch quietly once its mission is done: roslaunch shuts
// every node down on SIGINT, as when the user presses Ctrl-C (no "REQUIRED
// process has died" banner, rosbag closes its bag).
#include <string>

namespace gather {

// True when the parent of this process is roslaunch (its command line
// names roslaunch): the only process end_launch() signals.
bool parent_is_roslaunch();

// Sends SIGINT to the parent roslaunch; false (nothing sent) when the
// parent is not roslaunch.
bool end_launch();

}  // namespace gather
