#pragma once
// The mission video's encoder, behind an interface: OpenCV's video I/O (and
// the FFmpeg and GStreamer libraries behind it) lives in a module of its own,
// libgather_video.so, loaded only when a video is written
// (load_video_sink()), so that no other gather command pays for loading it.
#include <opencv2/core.hpp>

#include <memory>
#include <string>

namespace gather {
namespace figures {

class VideoSink {
 public:
  virtual ~VideoSink() = default;
  // Opens `path` for frames of `size` at `fps`, encoded with the FourCC
  // `codec` (4 characters: "mp4v", "MJPG") through FFmpeg; false if it cannot.
  virtual bool open(const std::string& path, const std::string& codec, double fps, cv::Size size) = 0;
  virtual void write(const cv::Mat& frame) = 0;  // an 8-bit BGR frame of the size opened
  virtual void release() = 0;
};

// The module's entry point: a new sink, owned by the caller.
using MakeVideoSink = VideoSink* (*)();
constexpr const char* kMakeVideoSink = "gather_make_video_sink";

// Loads libgather_video.so (kept loaded) and makes a sink. It is looked for
// beside the library or program this code is linked into, then where it is
// installed, then where it was built, then by the dynamic linker's search.
// Throws gather::Error("<what>: ...") naming the places tried when none loads.
std::unique_ptr<VideoSink> load_video_sink(const std::string& what);

}  // namespace figures
}  // namespace gather
