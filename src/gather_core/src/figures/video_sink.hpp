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

// The module's entry points: a new sink, owned by the caller; and the
// version of this interface it was built with (kVideoSinkAbi: raise it when
// VideoSink changes), so that a module left from another build is skipped.
using MakeVideoSink = VideoSink* (*)();
using VideoSinkAbi = int (*)();
constexpr const char* kMakeVideoSink = "gather_make_video_sink";
constexpr const char* kVideoSinkAbiName = "gather_video_sink_abi";
constexpr int kVideoSinkAbi = 1;

// Loads libgather_video.so (kept loaded) and makes a sink. It is looked for
// beside the library this code is linked into, beside the running program
// and in its ../lib, where it was built, where it is installed, then by the
// dynamic linker's search; a module of another kVideoSinkAbi is skipped.
// Throws gather::Error("<what>: ...") naming the places tried when none loads.
std::unique_ptr<VideoSink> load_video_sink(const std::string& what);

}  // namespace figures
}  // namespace gather
