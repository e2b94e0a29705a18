#include "gather_agent/runner/pipe_world.hpp"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "gather_agent/transport/lcm_robot.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

constexpr uint32_t kMaxFrame = 65536;

bool write_all(int fd, const uint8_t* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::write(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k, n -= static_cast<std::size_t>(k);
  }
  return true;
}

bool read_all(int fd, uint8_t* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::read(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k, n -= static_cast<std::size_t>(k);
  }
  return true;
}

}  // namespace

bool write_frame(int fd, PipeFrame kind, const uint8_t* payload, uint32_t size) {
  uint8_t head[5] = {static_cast<uint8_t>(kind), static_cast<uint8_t>(size), static_cast<uint8_t>(size >> 8),
                     static_cast<uint8_t>(size >> 16), static_cast<uint8_t>(size >> 24)};
  return write_all(fd, head, sizeof head) && (size == 0 || write_all(fd, payload, size));
}

bool read_frame(int fd, PipeFrame& kind, std::vector<uint8_t>& payload, uint32_t max) {
  uint8_t head[5];
  if (!read_all(fd, head, sizeof head)) return false;
  const uint32_t size = static_cast<uint32_t>(head[1]) | static_cast<uint32_t>(head[2]) << 8 |
                        static_cast<uint32_t>(head[3]) << 16 | static_cast<uint32_t>(head[4]) << 24;
  if (size > max) return false;
  kind = static_cast<PipeFrame>(head[0]);
  payload.resize(size);
  return size == 0 || read_all(fd, payload.data(), size);
}

PipeWorld::PipeWorld(std::vector<std::string> command, int agents) : agents_(agents) {
  command.push_back("--pipe");
  int down[2], up[2];
  if (::pipe(down) != 0 || ::pipe(up) != 0) throw Error(command[0], std::string("pipe: ") + std::strerror(errno));
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ < 0) throw Error(command[0], std::string("fork failed: ") + std::strerror(errno));
  if (pid_ == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive the run
    if (getppid() != parent) _exit(1);
    ::dup2(down[0], STDIN_FILENO);
    ::dup2(up[1], STDOUT_FILENO);
    ::close(down[0]), ::close(down[1]), ::close(up[0]), ::close(up[1]);
    std::vector<char*> argv;
    for (std::string& a : command) argv.push_back(&a[0]);
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    std::fprintf(stderr, "gather run: cannot run %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  ::close(down[0]), ::close(up[1]);
  to_ = down[1], from_ = up[0];
  ::signal(SIGPIPE, SIG_IGN);  // a world that died is reported by step(), not by a signal
  buffer_.reserve(kMaxFrame);
}

PipeWorld::~PipeWorld() {
  if (to_ >= 0) {
    write_frame(to_, PipeFrame::kQuit, nullptr, 0);
    ::close(to_);
  }
  if (from_ >= 0) ::close(from_);
  if (pid_ > 0) {
    int status = 0;
    for (int i = 0; i < 200; ++i) {  // 2 s to end by itself
      if (waitpid(pid_, &status, WNOHANG) == pid_) return;
      usleep(10000);
    }
    ::kill(pid_, SIGKILL);
    waitpid(pid_, &status, 0);
  }
}

void PipeWorld::failed(const std::string& what, bool said) {
  std::string why = what;
  // Its own words when it left some (an error frame before it exited).
  PipeFrame kind;
  std::vector<uint8_t> last;
  if (!said && from_ >= 0 && read_frame(from_, kind, last, kMaxFrame) && kind == PipeFrame::kError)
    why.assign(last.begin(), last.end());
  // Its exit status says whether it refused its input (2: bad input here too).
  int status = 0;
  bool ended = false;
  for (int i = 0; pid_ > 0 && i < 300 && !ended; ++i) {
    ended = waitpid(pid_, &status, WNOHANG) == pid_;
    if (!ended) usleep(10000);
  }
  if (ended) pid_ = -1;
  if (ended && WIFEXITED(status) && WEXITSTATUS(status) == 2) throw Error("gather_world", why);
  if (ended && WIFEXITED(status) && WEXITSTATUS(status) != 0 && !said)
    throw RuntimeError("gather_world", why + " (it exited with status " + std::to_string(WEXITSTATUS(status)) + ")");
  if (ended && WIFSIGNALED(status))
    throw RuntimeError("gather_world", why + " (killed by signal " + std::to_string(WTERMSIG(status)) + ")");
  throw RuntimeError("gather_world", why);
}

void PipeWorld::step(int64_t tick, double t, const std::vector<NavCommand>& commands, std::vector<RobotPose>& poses,
                     std::vector<NavStatus>& statuses) {
  for (const NavCommand& c : commands) {
    if (!encode_robot(c, buffer_))
      failed("a navigation command of agent " + std::to_string(c.agent) + " does not encode");
    if (!write_frame(to_, PipeFrame::kCommand, buffer_.data(), static_cast<uint32_t>(buffer_.size())))
      failed("its pipe closed");
  }
  uint8_t step[16];
  std::memcpy(step, &tick, 8);
  std::memcpy(step + 8, &t, 8);
  if (!write_frame(to_, PipeFrame::kStep, step, sizeof step)) failed("its pipe closed");
  poses.clear(), statuses.clear();
  for (;;) {
    PipeFrame kind;
    if (!read_frame(from_, kind, buffer_, kMaxFrame)) failed("it ended at tick " + std::to_string(tick));
    const int n = static_cast<int>(buffer_.size());
    switch (kind) {
      case PipeFrame::kDone: return;
      case PipeFrame::kPose:
        poses.emplace_back();
        if (decode_robot(buffer_.data(), n, poses.back()) != RobotDecoded::kOk || poses.back().agent >= agents_)
          failed("a pose that does not decode at tick " + std::to_string(tick));
        break;
      case PipeFrame::kStatus:
        statuses.emplace_back();
        if (decode_robot(buffer_.data(), n, statuses.back()) != RobotDecoded::kOk || statuses.back().agent >= agents_)
          failed("a status that does not decode at tick " + std::to_string(tick));
        break;
      case PipeFrame::kError: failed(std::string(buffer_.begin(), buffer_.end()), true);
      default: failed("an unknown frame at tick " + std::to_string(tick));
    }
  }
}

}  // namespace agent
}  // namespace gather
