// runner/pipe_world: the framing of gather run's pipe to gather_world
// ([kind: 1 byte][length: 4 bytes, little endian][payload]) over a pipe(2)
// pair: every kind survives the round trip (the robot interface's messages
// in their LCM encoding), a frame longer than the reader's bound is
// refused, the end of the pipe (before a frame, or inside one) ends
// reading, and a pipe nobody reads refuses writing. PipeWorld itself
// (gather_world as a child process) is tested end to end
// (tests/e2e/robots_e2e.py).
#include "gather_agent/runner/pipe_world.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <string>
#include <vector>

#include "gather_agent/transport/lcm_robot.hpp"

namespace gather {
namespace agent {
namespace {

// A pipe, both ends closed at the end of the test.
struct Pipe {
  int fd[2] = {-1, -1};
  Pipe() { EXPECT_EQ(::pipe(fd), 0); }
  ~Pipe() {
    close_write();
    if (fd[0] >= 0) ::close(fd[0]);
  }
  void close_write() {
    if (fd[1] >= 0) ::close(fd[1]);
    fd[1] = -1;
  }
  int in() const { return fd[1]; }
  int out() const { return fd[0]; }
};

std::vector<uint8_t> raw(int fd, std::size_t n) {
  std::vector<uint8_t> b(n);
  std::size_t got = 0;
  while (got < n) {
    const ssize_t k = ::read(fd, b.data() + got, n - got);
    if (k <= 0) break;
    got += static_cast<std::size_t>(k);
  }
  b.resize(got);
  return b;
}

TEST(PipeFrame, TheHeadIsTheKindThenTheLengthLittleEndian) {
  Pipe p;
  std::vector<uint8_t> payload(258);
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<uint8_t>(i * 7);
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kPose, payload.data(), static_cast<uint32_t>(payload.size())));
  const std::vector<uint8_t> b = raw(p.out(), 5 + payload.size());
  ASSERT_EQ(b.size(), 5 + payload.size());
  EXPECT_EQ(b[0], 'P');
  EXPECT_EQ(b[1], 0x02);  // 258 = 0x0102
  EXPECT_EQ(b[2], 0x01);
  EXPECT_EQ(b[3], 0x00);
  EXPECT_EQ(b[4], 0x00);
  EXPECT_EQ(std::vector<uint8_t>(b.begin() + 5, b.end()), payload);
  // An empty frame is its head alone.
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kDone, nullptr, 0));
  EXPECT_EQ(raw(p.out(), 5), (std::vector<uint8_t>{'D', 0, 0, 0, 0}));
}

TEST(PipeFrame, EveryKindSurvivesTheRoundTripInOrder) {
  Pipe p;
  // What the parent writes in a tick, and what the world answers.
  NavCommand c;
  c.agent = 2, c.tick = 11, c.id = 3, c.kind = NavCommand::Kind::kGo, c.n = 2;
  c.points[0] = Point2{1.5, 2.5}, c.points[1] = Point2{3.5, 0.25};
  c.after[0] = 1.0, c.after[1] = 3.0, c.tolerance[0] = 0.25, c.tolerance[1] = 1.0;
  std::vector<uint8_t> command;
  ASSERT_TRUE(encode_robot(c, command));
  RobotPose pose;
  pose.agent = 2, pose.tick = 11, pose.stamp = 1.1, pose.at = Point2{1.75, 2.25}, pose.heading = 0.5;
  std::vector<uint8_t> pose_bytes;
  ASSERT_TRUE(encode_robot(pose, pose_bytes));
  NavStatus status;
  status.agent = 2, status.tick = 11, status.stamp = 1.1, status.command = 3, status.state = NavState::kActive;
  status.reached = 1, status.reached_at[0] = 0.9;
  std::vector<uint8_t> status_bytes;
  ASSERT_TRUE(encode_robot(status, status_bytes));
  const int64_t tick = 11;
  const double t = 1.1;
  uint8_t step[16];
  std::memcpy(step, &tick, 8);
  std::memcpy(step + 8, &t, 8);
  const std::string error = "gather_world: robot.max_speed = 0 must be in (0, 10] m/s";

  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kCommand, command.data(), static_cast<uint32_t>(command.size())));
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kStep, step, sizeof step));
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kPose, pose_bytes.data(), static_cast<uint32_t>(pose_bytes.size())));
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kStatus, status_bytes.data(), static_cast<uint32_t>(status_bytes.size())));
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kDone, nullptr, 0));
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kError, reinterpret_cast<const uint8_t*>(error.data()),
                          static_cast<uint32_t>(error.size())));
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kQuit, nullptr, 0));

  PipeFrame kind;
  std::vector<uint8_t> got(3, 0xee);  // a reader's buffer holds the previous frame: resized to each
  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kCommand);
  EXPECT_EQ(got, command);
  NavCommand gc;
  ASSERT_EQ(decode_robot(got.data(), static_cast<int>(got.size()), gc), RobotDecoded::kOk);
  EXPECT_EQ(gc.tolerance[1], 1.0);
  EXPECT_EQ(gc.points[1].x, 3.5);

  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kStep);
  ASSERT_EQ(got.size(), 16u);
  int64_t got_tick = 0;
  double got_t = 0.0;
  std::memcpy(&got_tick, got.data(), 8);
  std::memcpy(&got_t, got.data() + 8, 8);
  EXPECT_EQ(got_tick, 11);
  EXPECT_EQ(got_t, 1.1);

  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kPose);
  RobotPose gp;
  ASSERT_EQ(decode_robot(got.data(), static_cast<int>(got.size()), gp), RobotDecoded::kOk);
  EXPECT_EQ(gp.at.x, 1.75);
  EXPECT_EQ(gp.heading, 0.5);

  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kStatus);
  NavStatus gs;
  ASSERT_EQ(decode_robot(got.data(), static_cast<int>(got.size()), gs), RobotDecoded::kOk);
  EXPECT_EQ(gs.state, NavState::kActive);
  EXPECT_EQ(gs.reached_at[0], 0.9);

  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kDone);
  EXPECT_TRUE(got.empty());

  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kError);
  EXPECT_EQ(std::string(got.begin(), got.end()), error);

  ASSERT_TRUE(read_frame(p.out(), kind, got, 65536));
  EXPECT_EQ(kind, PipeFrame::kQuit);
  EXPECT_TRUE(got.empty());

  // Then the end of the pipe.
  p.close_write();
  EXPECT_FALSE(read_frame(p.out(), kind, got, 65536));
}

TEST(PipeFrame, AFrameLongerThanTheBoundIsRefused) {
  Pipe p;
  std::vector<uint8_t> payload(100, 0x42);
  ASSERT_TRUE(write_frame(p.in(), PipeFrame::kPose, payload.data(), 100));
  PipeFrame kind = PipeFrame::kDone;
  std::vector<uint8_t> got;
  EXPECT_FALSE(read_frame(p.out(), kind, got, 99));
  EXPECT_TRUE(got.empty());  // nothing was read into it
  // At the bound itself, a frame is read.
  Pipe q;
  ASSERT_TRUE(write_frame(q.in(), PipeFrame::kStatus, payload.data(), 100));
  ASSERT_TRUE(read_frame(q.out(), kind, got, 100));
  EXPECT_EQ(kind, PipeFrame::kStatus);
  EXPECT_EQ(got, payload);
  // A head that claims 4 GiB - 1 (a world gone mad) is refused before anything is allocated.
  Pipe r;
  const uint8_t huge[5] = {'P', 0xff, 0xff, 0xff, 0xff};
  ASSERT_EQ(::write(r.in(), huge, 5), 5);
  EXPECT_FALSE(read_frame(r.out(), kind, got, 65536));
  EXPECT_EQ(got.size(), 100u);  // the previous frame's, untouched
}

TEST(PipeFrame, TheEndOfThePipeBeforeOrInsideAFrameEndsReading) {
  PipeFrame kind;
  std::vector<uint8_t> got;
  {
    Pipe p;  // nothing written
    p.close_write();
    EXPECT_FALSE(read_frame(p.out(), kind, got, 65536));
  }
  {
    Pipe p;  // half a head
    const uint8_t head[3] = {'T', 10, 0};
    ASSERT_EQ(::write(p.in(), head, 3), 3);
    p.close_write();
    EXPECT_FALSE(read_frame(p.out(), kind, got, 65536));
  }
  {
    Pipe p;  // a head for 10 bytes, 4 of them
    const uint8_t part[9] = {'T', 10, 0, 0, 0, 1, 2, 3, 4};
    ASSERT_EQ(::write(p.in(), part, 9), 9);
    p.close_write();
    EXPECT_FALSE(read_frame(p.out(), kind, got, 65536));
  }
}

TEST(PipeFrame, WritingToAPipeNobodyReadsFails) {
  // PipeWorld ignores SIGPIPE (a world that died is reported by step()).
  struct sigaction ignore = {};
  struct sigaction before = {};
  ignore.sa_handler = SIG_IGN;
  ASSERT_EQ(::sigaction(SIGPIPE, &ignore, &before), 0);
  Pipe p;
  ::close(p.fd[0]);
  p.fd[0] = -1;
  const uint8_t one = 1;
  EXPECT_FALSE(write_frame(p.in(), PipeFrame::kCommand, &one, 1));
  EXPECT_FALSE(write_frame(p.in(), PipeFrame::kQuit, nullptr, 0));
  ::sigaction(SIGPIPE, &before, nullptr);
}

}  // namespace
}  // namespace agent
}  // namespace gather
