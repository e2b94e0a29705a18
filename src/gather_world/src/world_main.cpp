// gather_world: the robots of a team (MrptWorld), behind the robot
// interface. With --pipe it is the child of `gather run --robots mrpt`
// (frames on stdin and stdout: runner/pipe_world.hpp); otherwise it speaks
// LCM: it takes the OC's plan announcement and ticks (lockstep: each tick
// after every command of the tick before; wall clock: every navigation tick
// of wall time), the agents' commands, and publishes every robot's pose and
// status (docs/robots.md), and with --scans HZ each robot's laser scan HZ
// times a second of mission time (for views: mission.launch laser:=true).
// Exit status: 0 the mission ended (or SIGINT/SIGTERM, or the parent's
// quit), 2 bad input (a flag, the plan, the world YAML, the OC's plan is
// not this one), 1 a failure while running (the OC went silent, a pipe
// broke).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/runner/pipe_world.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/shutdown_signal.hpp"
#include "gather_agent/transport/lcm_robot.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/worker_policy.hpp"
#include "gather_core/mission/world.hpp"
#include "gather_world/mrpt_world.hpp"

namespace {

using gather::Error;
using gather::Point2;
namespace agent = gather::agent;
namespace world = gather::world;
using Clock = std::chrono::steady_clock;

const char* kUsage =
    "usage: gather_world --plan PLAN_DIR [--config WORLD_YAML] (--pipe | (--key-file F | --insecure) "
    "[--lcm-url URL] [--reply-url URL] [--robot-url URL] [--silence S] [--scans HZ])";

struct Options {
  std::string plan, config, lcm_url, reply_url, robot_url, key_file;
  bool pipe = false, insecure = false, help = false;
  double silence_s = 30.0;
  double scans_hz = 0.0;  // 0: no scans
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("gather_world", a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      o.help = true;
    } else if (a == "--plan") {
      o.plan = value();
    } else if (a == "--config") {
      o.config = value();
    } else if (a == "--pipe") {
      o.pipe = true;
    } else if (a == "--lcm-url") {
      o.lcm_url = value();
    } else if (a == "--reply-url") {
      o.reply_url = value();
    } else if (a == "--robot-url") {
      o.robot_url = value();
    } else if (a == "--key-file") {
      o.key_file = value();
    } else if (a == "--insecure") {
      o.insecure = true;
    } else if (a == "--silence") {
      const std::string v = value();
      char* end = nullptr;
      o.silence_s = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(o.silence_s > 0 && o.silence_s <= 86400))
        throw Error("gather_world", "--silence must be in (0, 86400] s, got '" + v.substr(0, 40) + "'");
    } else if (a == "--scans") {
      const std::string v = value();
      char* end = nullptr;
      o.scans_hz = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(o.scans_hz >= 0 && o.scans_hz <= 50))
        throw Error("gather_world", "--scans must be in [0, 50] Hz of mission time, got '" + v.substr(0, 40) + "'");
    } else {
      throw Error("gather_world", "unexpected argument '" + a.substr(0, 60) + "' (" + kUsage + ")");
    }
  }
  if (o.help) return o;
  if (o.plan.empty()) throw Error("gather_world", std::string("--plan is required (") + kUsage + ")");
  if (o.pipe && (!o.lcm_url.empty() || !o.robot_url.empty() || !o.key_file.empty() || o.insecure))
    throw Error("gather_world", "--pipe takes no LCM flag (it talks to its parent over stdin and stdout)");
  if (o.pipe && o.scans_hz > 0) throw Error("gather_world", "--scans needs LCM (with --pipe nobody looks at them)");
  return o;
}

// Every robot's pose and status of `tick` to the agents.
void publish(agent::LcmRobotLink& link, const std::vector<agent::RobotPose>& poses,
             const std::vector<agent::NavStatus>& statuses) {
  for (const agent::RobotPose& p : poses) link.publish(p);
  for (const agent::NavStatus& s : statuses) link.publish(s);
}

// Every robot's last scan, when one is due at mission time `t` (--scans).
class ScanPublisher {
 public:
  explicit ScanPublisher(double hz) : period_(hz > 0 ? 1.0 / hz : 0.0) {}
  void maybe(world::MrptWorld& w, agent::LcmRobotLink& link, int64_t tick, double t) {
    if (period_ <= 0 || t + 1e-9 < next_) return;
    for (int k = 0; k < w.robots(); ++k) {
      w.scan(k, scan_);
      scan_.tick = tick;
      if (scan_.rays > 0) link.publish(scan_);
    }
    next_ = std::max(next_ + period_, t);
  }

 private:
  double period_, next_ = 0.0;
  agent::RobotScan scan_;
};

// The child of `gather run`: frames in, frames out, until it says quit.
int run_pipe(world::MrptWorld& w, int in, int out) {
  std::vector<agent::NavCommand> commands;
  std::vector<agent::RobotPose> poses;
  std::vector<agent::NavStatus> statuses;
  std::vector<uint8_t> payload, frame;
  commands.reserve(256);
  for (;;) {
    agent::PipeFrame kind;
    if (!agent::read_frame(in, kind, payload, 65536)) return 0;  // the parent is gone: nothing to do
    switch (kind) {
      case agent::PipeFrame::kCommand:
        commands.emplace_back();
        if (agent::decode_robot(payload.data(), static_cast<int>(payload.size()), commands.back()) !=
            agent::RobotDecoded::kOk)
          throw gather::RuntimeError("gather_world", "a navigation command from gather run does not decode");
        break;
      case agent::PipeFrame::kStep: {
        if (payload.size() != 16) throw gather::RuntimeError("gather_world", "a step frame of the wrong size");
        int64_t tick = 0;
        double t = 0.0;
        std::memcpy(&tick, payload.data(), 8);
        std::memcpy(&t, payload.data() + 8, 8);
        w.step(tick, t, commands, poses, statuses);
        commands.clear();
        for (const agent::RobotPose& p : poses)
          if (!agent::encode_robot(p, frame) ||
              !agent::write_frame(out, agent::PipeFrame::kPose, frame.data(), static_cast<uint32_t>(frame.size())))
            return 0;
        for (const agent::NavStatus& s : statuses)
          if (!agent::encode_robot(s, frame) ||
              !agent::write_frame(out, agent::PipeFrame::kStatus, frame.data(), static_cast<uint32_t>(frame.size())))
            return 0;
        if (!agent::write_frame(out, agent::PipeFrame::kDone, nullptr, 0)) return 0;
        break;
      }
      case agent::PipeFrame::kQuit: return 0;
      default: throw gather::RuntimeError("gather_world", "an unknown frame from gather run");
    }
  }
}

// Over LCM, on the OC's clock.
int run_lcm(world::MrptWorld& w, agent::LoadedPlan& plan, const Options& o, gather::ShutdownSignal& signal) {
  std::optional<agent::FleetKey> key = agent::fleet_key_from_options(o.key_file, o.insecure, "gather_world");
  const std::string url = o.lcm_url;
  agent::LcmFleet fleet(url, o.reply_url.empty() ? agent::LcmFleet::reply_url_for(url) : o.reply_url, false, key,
                        agent::kMaxTeam, /*radio=*/false);
  std::vector<int> ids;
  for (int k = 0; k < w.robots(); ++k) ids.push_back(k);
  // The plan's team and links: a master checks every tag of the OC's ticks
  // and plan, to every agent of it.
  fleet.set_team(plan.plan.file.agents.count(), {}, agent::plan_links(plan.plan.file));
  std::optional<agent::FleetKey> robot_key;
  if (key) robot_key = agent::robot_link_key(*key);
  agent::LcmRobotLink link(o.robot_url.empty() ? url : o.robot_url, agent::LcmRobotLink::Side::kRobots, ids, robot_key);
  const uint64_t digest = agent::plan_digest(plan);
  std::vector<agent::NavCommand> held, due;
  std::vector<agent::RobotPose> poses;
  std::vector<agent::NavStatus> statuses;
  ScanPublisher scans(o.scans_hz);
  held.reserve(1024), due.reserve(1024);
  bool planned = false, wall = false;
  double tick_s = 0.1, rate = 1.0;
  int64_t start_us = 0, next = 0;
  double wall_next = 0.0;
  agent::Tick pending;
  bool have_tick = false;
  auto heard = Clock::now(), said = Clock::now() - std::chrono::seconds(1), tick_since = Clock::now();
  auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  std::printf("gather_world: %d robots on %s, waiting for the OC\n", w.robots(), plan.dir.c_str());
  std::fflush(stdout);
  for (;;) {
    if (signal.wait_until(Clock::now())) return 0;
    fleet.handle(have_tick ? 5 : 20, link.fileno());
    link.handle(0);
    for (const agent::NavCommand& c : link.commands()) held.push_back(c);
    link.commands().clear();
    if (!fleet.plans().empty()) {
      heard = Clock::now();
      const agent::PlanAnnounce& p = fleet.plans().back();
      if (p.digest != digest) {
        std::fprintf(stderr, "gather_world: %s: not the plan the OC runs (digest differs)\n", plan.dir.c_str());
        return 2;
      }
      if (!p.robots) {
        std::fprintf(stderr, "gather_world: the OC runs its team on ideal bases, not on robots\n");
        return 2;
      }
      if (p.agents != w.robots()) {
        std::fprintf(stderr, "gather_world: the OC runs %d agents, the plan %d\n", p.agents, w.robots());
        return 2;
      }
      planned = true, wall = p.clock == agent::ClockMode::kWall, tick_s = p.tick, rate = p.rate;
      fleet.plans().clear();
    }
    // Before the mission: where the robots stand, now and then (an agent
    // says READY once its robot has reported).
    if (next == 0 && !have_tick && start_us == 0 && since(said) > 0.1) {
      w.step(-1, 0.0, {}, poses, statuses);
      publish(link, poses, statuses);
      said = Clock::now();
    }
    for (const agent::Tick& t : fleet.ticks()) {
      heard = Clock::now();
      if (!planned) continue;
      if (t.done) {
        std::printf("gather_world: mission over at t = %.1f s\n", t.t);
        return 0;
      }
      if (wall) {
        if (start_us == 0 && t.start_us > 0) start_us = t.start_us;
        continue;
      }
      if (t.tick < next) continue;
      if (!have_tick || t.tick < pending.tick) pending = t, have_tick = true, tick_since = Clock::now();
    }
    fleet.ticks().clear();
    if (wall && start_us > 0) {
      const double t = static_cast<double>(agent::wall_clock_us() - start_us) * 1e-6 * rate;
      if (t >= wall_next) {
        w.step(-1, std::max(0.0, t), held, poses, statuses);
        held.clear();
        publish(link, poses, statuses);
        scans.maybe(w, link, -1, t);
        wall_next = std::max(wall_next + tick_s, t);
      }
    }
    // A tick runs once every command of the tick before is in (or, lost on
    // the host, after 5 s without them).
    while (have_tick) {
      std::size_t n = 0;
      for (const agent::NavCommand& c : held) n += c.tick == pending.tick - 1;
      if (n < static_cast<std::size_t>(pending.commands_before) && since(tick_since) < 5.0) break;
      due.clear();
      for (const agent::NavCommand& c : held)
        if (c.tick < pending.tick) due.push_back(c);
      held.erase(
          std::remove_if(held.begin(), held.end(), [&](const agent::NavCommand& c) { return c.tick < pending.tick; }),
          held.end());
      std::stable_sort(due.begin(), due.end(), [](const agent::NavCommand& a, const agent::NavCommand& b) {
        return a.agent != b.agent ? a.agent < b.agent : a.id < b.id;
      });
      w.step(pending.tick, pending.t, due, poses, statuses);
      publish(link, poses, statuses);
      scans.maybe(w, link, pending.tick, pending.t);
      next = pending.tick + 1;
      have_tick = false;
    }
    if (since(heard) > o.silence_s) {
      std::fprintf(stderr, "gather_world: nothing heard from the OC for %g s on %s\n", o.silence_s,
                   url.empty() ? "LCM's default URL" : url.c_str());
      return 1;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  gather::ShutdownSignal shutdown;  // first: block the signals before LCM starts anything
  Options o;
  int out = STDOUT_FILENO;
  // One line: on stderr, and with --pipe in an error frame too (its parent
  // prints it as its own, naming gather_world).
  auto fail = [&](const std::exception& e, int status) {
    const std::string line = e.what();
    if (o.pipe)
      agent::write_frame(out, agent::PipeFrame::kError, reinterpret_cast<const uint8_t*>(line.data()),
                         static_cast<uint32_t>(line.size()));
    else
      std::fprintf(stderr, "%s\n", line.c_str());
    return status;
  };
  try {
    o = parse(argc, argv);
    if (o.help) {
      std::printf("%s\n", kUsage);
      return 0;
    }
    // With --pipe, stdout carries the frames: anything printed goes to stderr.
    if (o.pipe) {
      out = ::dup(STDOUT_FILENO);
      ::dup2(STDERR_FILENO, STDOUT_FILENO);
    }
    agent::LoadedPlan plan = agent::load_plan(o.plan);
    const world::WorldParams params = world::load_world_params(o.config);
    // The robots drive on the map at its own resolution; they start where
    // their agents believe they are (the start poses on the plan's grid).
    const gather::Scenario full = gather::load_scenario(plan.scenario.path);
    const gather::mission::World team_world(plan.scenario);
    const std::vector<Point2> starts = gather::mission::team_start_poses(
        team_world, plan.plan,
        gather::mission::oc_worker_homes(
            team_world, plan.plan,
            gather::mission::robot_protocol(gather::mission::ProtocolParams{}).home_clearance_m));
    world::MrptWorld w(full.grid, starts, full.team.speed, full.team.radius, params);
    return o.pipe ? run_pipe(w, STDIN_FILENO, out) : run_lcm(w, plan, o, shutdown);
  } catch (const gather::RuntimeError& e) {
    return fail(e, 1);
  } catch (const std::exception& e) {
    return fail(e, 2);
  }
}
