// Runs the real gather_agent binary: start-up, clean exit on SIGTERM/SIGINT
// within 1 s, and one-line errors with exit status 2 on bad input. LCM runs on
// memq:// (in-process), so these tests send nothing on any network.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

namespace {

const std::string kScenario = std::string(GATHER_REPO_DIR) + "/../shared/maps/ipa/office_a.scenario.yaml";

struct Child {
  pid_t pid = -1;
  int err_fd = -1;
};

Child spawn(const std::vector<std::string>& args) {
  int pipefd[2];
  EXPECT_EQ(pipe(pipefd), 0);
  Child c;
  c.pid = fork();
  if (c.pid == 0) {
    dup2(pipefd[1], 2);
    close(pipefd[0]);
    close(pipefd[1]);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(pipefd[1]);
  c.err_fd = pipefd[0];
  return c;
}

std::string read_all(int fd) {
  std::string s;
  char buf[512];
  ssize_t n;
  while ((n = read(fd, buf, sizeof buf)) > 0) s.append(buf, static_cast<std::size_t>(n));
  close(fd);
  return s;
}

// Waits up to `limit` for the child; returns its wait status, or -1 on timeout (then kills it).
int wait_for(pid_t pid, std::chrono::milliseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

void expect_clean_stop_on(int sig) {
  Child c = spawn({GATHER_AGENT_BIN, "--id", "3", "--lcm-url", "memq://", "--rate", "20", kScenario});
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // loading the map and running
  ASSERT_EQ(waitpid(c.pid, nullptr, WNOHANG), 0) << "agent exited before the signal: " << read_all(c.err_fd);
  const auto t0 = std::chrono::steady_clock::now();
  kill(c.pid, sig);
  const int status = wait_for(c.pid, std::chrono::milliseconds(1000));
  const auto took = std::chrono::steady_clock::now() - t0;
  const std::string err = read_all(c.err_fd);
  ASSERT_NE(status, -1) << "agent did not exit within 1 s of signal " << sig;
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << err;
  EXPECT_LT(took, std::chrono::milliseconds(1000));
  EXPECT_EQ(err, "");
}

TEST(AgentProcess, ExitsZeroWithinOneSecondOnSigterm) { expect_clean_stop_on(SIGTERM); }
TEST(AgentProcess, ExitsZeroWithinOneSecondOnSigint) { expect_clean_stop_on(SIGINT); }

void expect_bad_input(const std::vector<std::string>& args, const std::string& needle) {
  Child c = spawn(args);
  const int status = wait_for(c.pid, std::chrono::milliseconds(10000));
  const std::string err = read_all(c.err_fd);
  ASSERT_NE(status, -1) << "hung";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2) << err;
  ASSERT_FALSE(err.empty());
  EXPECT_EQ(err.find('\n'), err.size() - 1) << "expected one line: " << err;
  EXPECT_NE(err.find(needle), std::string::npos) << err;
}

TEST(AgentProcess, BadInputGivesOneLineAndStatus2) {
  expect_bad_input({GATHER_AGENT_BIN, kScenario}, "--id is required");
  expect_bad_input({GATHER_AGENT_BIN, "--id", "x", kScenario}, "--id");
  expect_bad_input({GATHER_AGENT_BIN, "--id", "0", "--bogus", kScenario}, "unknown option --bogus");
  expect_bad_input({GATHER_AGENT_BIN, "--id", "0", "/nonexistent/s.yaml"}, "/nonexistent/s.yaml");
  expect_bad_input({GATHER_AGENT_BIN, "--id", "20", "--lcm-url", "memq://", kScenario}, "not in the team");
  expect_bad_input({GATHER_AGENT_BIN, "--id", "0", "--lcm-url", "bogus://x", kScenario}, "cannot open LCM URL");
}

}  // namespace
