// Runs the real gather_agent binary: start-up, clean exit on SIGTERM/SIGINT
// within 1 s while it waits for the OC, and one-line errors with exit status 2
// on bad input. LCM runs on memq:// (in-process), so these tests send nothing
// on any network. The plan is maps/office planned once into a temp directory.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "gather_agent/agent_options.hpp"
#include "gather_agent/roles/role.hpp"
#include "gather_agent/runner/agent_keys.hpp"
#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_core/plan/plan_export.hpp"

namespace {

const std::string kScenario = std::string(GATHER_REPO_DIR) + "/maps/office.scenario.yaml";

// A plan of maps/office (pap, 4 collectors) in a temp directory, made once.
const std::string& plan_dir() {
  static const std::string dir = [] {
    const std::string d = ::testing::TempDir() + "/gather_agent_process_test_plan_" + std::to_string(::getpid());
    const gather::Scenario map = gather::load_scenario(kScenario);
    const gather::Scenario s = gather::on_planning_grid(map, gather::planning_factor(map));
    const gather::plan::PlanContext ctx(s);
    gather::plan::write_plan_directory(
        d, ctx, gather::plan::plan_configuration(ctx, gather::partition::Method::kPap, 4, gather::plan::grown_groups()),
        1);
    return d;
  }();
  return dir;
}

// A fleet key (mode 0600) in a temp directory, made once.
const std::string& key_file() {
  static const std::string path = [] {
    const std::string p = ::testing::TempDir() + "/gather_agent_process_test_" + std::to_string(::getpid()) + ".key";
    std::filesystem::remove(p);
    gather::agent::write_fleet_key(p, gather::agent::generate_fleet_key());
    return p;
  }();
  return path;
}

// Agent `id`'s own key file for the test plan, from key_file().
std::string agent_key_file(int id) {
  const std::string p = ::testing::TempDir() + "/gather_agent_process_test_" + std::to_string(::getpid()) + "_agent" +
                        std::to_string(id) + ".key";
  std::filesystem::remove(p);
  gather::agent::write_key_ring(p,
                                gather::agent::agent_keys_for(gather::agent::load_fleet_key(key_file()), id,
                                                              gather::plan::read_plan_file(plan_dir() + "/plan.yaml")));
  return p;
}

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
  Child c = spawn(
      {GATHER_AGENT_BIN, "--id", "3", "--lcm-url", "memq://", "--key-file", agent_key_file(3), "--plan", plan_dir()});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // loading the plan, waiting for the OC
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

// How long an agent waits for a silent OC: a simulation's process 30 s, an
// agent on a robot (the radio may be gone for minutes) kRobotSilence_s; an
// explicit --silence wins.
TEST(AgentOptions, OnARobotTheAgentWaitsLongerForTheOc) {
  using gather::kRobotSilence_s;
  auto parse = [](std::vector<std::string> args) {
    args.insert(args.begin(), "gather_agent");
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    return gather::parse_agent_options(static_cast<int>(argv.size()), argv.data());
  };
  EXPECT_EQ(parse({"--id", "1", "--plan", "p"}).silence_s, 30.0);
  EXPECT_EQ(parse({"--id", "1", "--plan", "p", "--motion", "lcm"}).silence_s, kRobotSilence_s);
  EXPECT_EQ(parse({"--id", "1", "--plan", "p", "--silence", "5", "--motion", "lcm"}).silence_s, 5.0);
  EXPECT_EQ(parse({"--id", "1", "--plan", "p", "--clock-skew", "-4.5"}).clock_skew_s, -4.5);
}

TEST(AgentProcess, BadInputGivesOneLineAndStatus2) {
  const std::string bin = GATHER_AGENT_BIN, plan = plan_dir(), key = key_file();
  expect_bad_input({bin, "--plan", plan}, "--id is required");
  expect_bad_input({bin, "--id", "0"}, "--plan is required");
  expect_bad_input({bin, "--id", "x", "--plan", plan}, "--id");
  expect_bad_input({bin, "--id", "0", "--bogus", "--plan", plan}, "unexpected argument '--bogus'");
  expect_bad_input({bin, "--id", "0", "--key-file", key, "--plan", "/nonexistent/plan"}, "/nonexistent/plan");
  expect_bad_input({bin, "--id", "20", "--lcm-url", "memq://", "--key-file", key, "--plan", plan},
                   "not in the plan's team of 20");
  expect_bad_input({bin, "--id", "0", "--lcm-url", "bogus://x", "--key-file", key, "--plan", plan},
                   "cannot open LCM URL");
  expect_bad_input({bin, "--id", "0", "--motion", "base", "--plan", plan},
                   "--motion must be sim (an ideal base) or lcm");
  expect_bad_input({bin, "--id", "0", "--motion", "wheels", "--plan", plan}, "--motion must be sim");
  expect_bad_input({bin, "--id", "0", "--robot-url", "memq://", "--plan", plan}, "--robot-url needs --motion lcm");
  expect_bad_input({bin, "--id", "0", "--clock-skew", "4000", "--plan", plan}, "--clock-skew must be in");
  expect_bad_input({bin, "--id", "0", "--clock-skew", "nan", "--plan", plan}, "--clock-skew expects a number");
  // Signed fleet traffic: a key or an explicit --insecure, never both; a key
  // others can read is refused.
  expect_bad_input({bin, "--id", "0", "--plan", plan}, "--key-file");
  expect_bad_input({bin, "--id", "0", "--key-file", key, "--insecure", "--plan", plan}, "not both");
  expect_bad_input({bin, "--id", "0", "--key-file", "/nonexistent/fleet.key", "--plan", plan},
                   "/nonexistent/fleet.key");
  const std::string open_key = ::testing::TempDir() + "/gather_agent_open_" + std::to_string(::getpid()) + ".key";
  std::filesystem::remove(open_key);
  // Per-agent keys: another agent's file, or one whose links are not the plan's.
  expect_bad_input({bin, "--id", "0", "--lcm-url", "memq://", "--key-file", agent_key_file(3), "--plan", plan},
                   "agent 3's key file, given to agent 0");
  const gather::agent::FleetKey master = gather::agent::load_fleet_key(key);
  const std::string stray = ::testing::TempDir() + "/gather_agent_stray_" + std::to_string(::getpid()) + ".key";
  std::filesystem::remove(stray);
  std::vector<int16_t> peers =
      gather::agent::plan_links(gather::plan::read_plan_file(plan + "/plan.yaml")).peers(0);  // and one more:
  const std::size_t plan_peers = peers.size();
  for (int16_t k = 1; k < 20 && peers.size() == plan_peers; ++k)
    if (std::find(peers.begin(), peers.end(), k) == peers.end()) peers.push_back(k);
  gather::agent::write_key_ring(stray, gather::agent::agent_key_ring(master, 0, peers));
  expect_bad_input({bin, "--id", "0", "--lcm-url", "memq://", "--key-file", stray, "--plan", plan},
                   "its plan links it to");
  std::filesystem::remove(stray);
  std::filesystem::copy_file(key, open_key);
  ::chmod(open_key.c_str(), 0644);
  expect_bad_input({bin, "--id", "0", "--key-file", open_key, "--plan", plan}, "chmod 600");
  std::filesystem::remove(open_key);
}

TEST(AgentProcess, ExitsOneWhenTheOcStaysSilent) {
  Child c = spawn(
      {GATHER_AGENT_BIN, "--id", "2", "--lcm-url", "memq://", "--silence", "1", "--insecure", "--plan", plan_dir()});
  const int status = wait_for(c.pid, std::chrono::milliseconds(15000));
  const std::string err = read_all(c.err_fd);
  ASSERT_NE(status, -1) << "hung";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << err;
  EXPECT_NE(err.find("nothing heard from the OC for 1 s"), std::string::npos) << err;
  EXPECT_NE(err.find("WARNING: --insecure"), std::string::npos) << err;  // said at start
}

TEST(AgentProcess, APlanThatDoesNotMatchItsScenarioIsRefused) {
  namespace fs = std::filesystem;
  const std::string bad = ::testing::TempDir() + "/gather_agent_bad_plan_" + std::to_string(::getpid());
  fs::remove_all(bad);
  fs::copy(plan_dir(), bad);
  // One agent more than the scenario's team.
  std::ifstream in(bad + "/plan.yaml");
  std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  yaml.replace(yaml.find("routes:"), 7, "  - {id: 20, role: worker, segment: 17, collector: -1}\nroutes:");
  std::ofstream(bad + "/plan.yaml") << yaml;
  expect_bad_input({GATHER_AGENT_BIN, "--id", "0", "--lcm-url", "memq://", "--key-file", key_file(), "--plan", bad},
                   "plan.yaml");
  fs::remove_all(bad);
}

}  // namespace
