// libgather_video.so: the mission video's encoder (video_sink.hpp), OpenCV's
// VideoWriter through FFmpeg. Loaded by figures::load_video_sink().
#include <opencv2/videoio.hpp>

#include "video_sink.hpp"

namespace gather {
namespace figures {
namespace {

class OpenCvVideoSink : public VideoSink {
 public:
  bool open(const std::string& path, const std::string& codec, double fps, cv::Size size) override {
    if (codec.size() != 4) return false;
    const int fourcc = cv::VideoWriter::fourcc(codec[0], codec[1], codec[2], codec[3]);
    return writer_.open(path, cv::CAP_FFMPEG, fourcc, fps, size);
  }
  void write(const cv::Mat& frame) override { writer_.write(frame); }
  void release() override { writer_.release(); }

 private:
  cv::VideoWriter writer_;
};

}  // namespace
}  // namespace figures
}  // namespace gather

extern "C" __attribute__((visibility("default"))) gather::figures::VideoSink* gather_make_video_sink() {
  return new gather::figures::OpenCvVideoSink();
}

extern "C" __attribute__((visibility("default"))) int gather_video_sink_abi() { return gather::figures::kVideoSinkAbi; }
