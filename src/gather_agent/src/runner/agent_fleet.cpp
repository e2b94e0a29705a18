#include "gather_agent/runner/agent_fleet.hpp"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <thread>

#include "gather_core/error.hpp"

namespace gather {
namespace {

bool executable(const std::string& p) {
  struct stat st;
  return !p.empty() && ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && access(p.c_str(), X_OK) == 0;
}

std::vector<std::string> split(const char* s, char sep) {
  std::vector<std::string> out;
  if (!s) return out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

int decode_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace

namespace {

// Binary `name` of catkin package `name`: beside the running binary
// (devel/lib/gather_core/gather -> devel/lib/<name>/<name> with catkin;
// build/plain/gather_core/gather -> build/plain/<name>, or one level up,
// with plain CMake), under CMAKE_PREFIX_PATH, or on PATH.
std::string find_binary(const std::string& explicit_path, const std::string& name) {
  if (!explicit_path.empty()) return executable(explicit_path) ? explicit_path : "";
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    self[n] = '\0';
    std::string dir(self);
    dir = dir.substr(0, dir.rfind('/'));
    for (const std::string& p :
         {dir + "/" + name, dir + "/../" + name + "/" + name, dir + "/../" + name, dir + "/../../" + name})
      if (executable(p)) return p;
  }
  for (const auto& prefix : split(std::getenv("CMAKE_PREFIX_PATH"), ':')) {
    const std::string p = prefix + "/lib/" + name + "/" + name;
    if (executable(p)) return p;
  }
  for (const auto& dir : split(std::getenv("PATH"), ':')) {
    const std::string p = dir + "/" + name;
    if (executable(p)) return p;
  }
  return "";
}

}  // namespace

std::string find_agent_binary(const std::string& explicit_path) { return find_binary(explicit_path, "gather_agent"); }
std::string find_world_binary(const std::string& explicit_path) { return find_binary(explicit_path, "gather_world"); }

AgentFleet::AgentFleet(std::vector<std::string> command, int agents) : command_(std::move(command)) {
  for (int i = 0; i < agents; ++i) agents_.push_back(AgentProcess{i});
}

AgentFleet::~AgentFleet() { stop(1.0); }

void AgentFleet::start() {
  for (AgentProcess& a : agents_) launch(a, {});
}

void AgentFleet::kill(int id) {
  AgentProcess& a = agents_.at(static_cast<std::size_t>(id));
  if (!a.running) return;
  int status = 0;
  ::kill(a.pid, SIGKILL);
  if (waitpid(a.pid, &status, 0) == a.pid) a.exit_status = decode_status(status);
  a.running = false;
  a.exited_early = true;
}

void AgentFleet::respawn(int id, const std::vector<std::string>& extra) {
  AgentProcess& a = agents_.at(static_cast<std::size_t>(id));
  kill(id);  // reaped first (SIGKILL ends it at once)
  ++a.restarts;
  launch(a, extra);
}

void AgentFleet::launch(AgentProcess& a, const std::vector<std::string>& extra) {
  const pid_t parent = getpid();
  {
    std::vector<std::string> args = command_;
    args.insert(args.end(), extra.begin(), extra.end());
    for (auto& arg : args) {
      const auto at = arg.find("{id}");
      if (at != std::string::npos) arg.replace(at, 4, std::to_string(a.id));
    }
    std::vector<char*> argv;
    for (auto& arg : args) argv.push_back(&arg[0]);
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) throw Error("fleet", std::string("fork failed: ") + std::strerror(errno));
    if (pid == 0) {
      // Own process group: roslaunch signals the fleet's group on shutdown, and
      // the fleet, not roslaunch, stops (and times) its agents.
      setpgid(0, 0);
      prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive the fleet launcher
      if (getppid() != parent) _exit(1);
      sigset_t none;
      sigemptyset(&none);
      sigprocmask(SIG_SETMASK, &none, nullptr);
      execv(argv[0], argv.data());
      std::fprintf(stderr, "fleet: cannot run %s: %s\n", argv[0], std::strerror(errno));
      _exit(127);
    }
    a.pid = pid;
    a.running = true;
    a.exited_early = false;
  }
}

std::vector<int> AgentFleet::poll() {
  std::vector<int> ended;
  for (AgentProcess& a : agents_) {
    if (!a.running) continue;
    int status = 0;
    if (waitpid(a.pid, &status, WNOHANG) == a.pid) {
      a.running = false;
      a.exited_early = true;
      a.exit_status = decode_status(status);
      ended.push_back(a.id);
    }
  }
  return ended;
}

bool AgentFleet::wait(double seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    poll();
    bool running = false;
    for (const AgentProcess& a : agents_) running = running || a.running;
    if (!running) return true;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > seconds) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void AgentFleet::stop(double grace_s) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  for (AgentProcess& a : agents_)
    if (a.running) ::kill(a.pid, SIGTERM);
  bool any = true;
  bool killed = false;
  while (any) {
    any = false;
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    for (AgentProcess& a : agents_) {
      if (!a.running) continue;
      int status = 0;
      const pid_t r = waitpid(a.pid, &status, WNOHANG);
      if (r == a.pid || r < 0) {  // r < 0: already reaped elsewhere
        a.running = false;
        a.exit_status = r < 0 ? -1 : decode_status(status);
        a.stop_latency_s = t;
      } else {
        any = true;
        if (t > grace_s && !killed) {
          for (AgentProcess& b : agents_)
            if (b.running) ::kill(b.pid, SIGKILL);
          killed = true;
        }
      }
    }
    if (any) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace gather
