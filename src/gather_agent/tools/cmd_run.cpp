// gather run PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--tick DT]
//                     [--loss P] [--loss-seed N] [--kill ID@T[,ID@T...]] [--repair merge|none]
//                     [--silent-intervals K] [--restart ID@T[,ID@T...]]
//                     [--robots ideal|mrpt [--world-config YAML] [--world-bin FILE]] [--protocol ideal|robots]
//                     [--speed-factor F]
//                     [--lcm (--key-file F | --insecure) [--lcm-url URL] [--reply-url URL]
//                            [--agent-bin FILE] [--rate R] [--clock lockstep|wall] [--agents spawn|external]]:
// runs the plan with the agent runtime for K seeds: every role in this
// process over an in-memory bus under the range gate and the lockstep
// clock, or with --lcm one gather_agent process per agent over LCM (this
// process is the OC and drives the clock; same roles, same gate, same
// clock: the same goals.csv). Writes goals.csv, cycles.csv, summary.csv in
// the schema of `gather sim`, and agents.csv (per agent and seed: role,
// goals measured / carried / delivered, messages sent / received / gated /
// lost). --lcm sends UDP multicast: only inside a private network namespace
// (tools/netns-run) or with an explicit --lcm-url. --clock wall runs the
// fleet as real robots would (no ticks: mission time is the wall clock x
// --rate, default 1): not reproducible, no per-agent counters. --kill ends
// agents at mission times (over LCM: SIGKILL to their processes); the OC
// declares silent agents dead and the survivors run the repaired plan
// (docs/faults.md). --robots mrpt runs the team on gather_world's robots
// (docs/robots.md): with the agents in this process, gather_world is its
// child over a pipe; with --lcm, one more process speaking the robot
// interface over LCM, every agent started with --motion lcm. --agents
// external (with --robots external --clock wall): this process is only the
// OC; the agents run on the robots (robot.launch) and join within 300 s.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_agent/runner/agent_fleet.hpp"
#include "gather_agent/runner/agent_keys.hpp"
#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/runner/pipe_world.hpp"
#include "gather_agent/runner/replay.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/mission_csv.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {
namespace {

// The robots of a run, when not ideal: gather_world's binary and its
// settings, or robots someone else drives (their drivers speak the robot
// interface over LCM).
struct Robots {
  std::string world_bin;     // "": ideal bases, or external robots
  std::string world_config;  // its YAML ("": defaults)
  bool external = false;
  bool any() const { return external || !world_bin.empty(); }
};

// Agents this process does not start (--agents external): they run on the
// robots (robot.launch) and join over LCM.
struct Fleet {
  bool external = false;
};

// One run with one gather_agent process per agent; this process is the OC.
agent::RunOutcome run_over_lcm(agent::TeamSetup& team, const agent::LoadedPlan& plan, uint64_t digest,
                               const agent::RunOptions& opt, double rate, bool wall, const std::string& url,
                               const std::string& reply_url, const std::string& agent_bin, const std::string& key_file,
                               const std::optional<agent::FleetKey>& key, const std::string& keys_dir,
                               const Robots& robots, const Fleet& fleet_of) {
  agent::LcmFleet fleet(url, reply_url, true, key, team.agents());
  std::vector<std::string> command{agent_bin,   "--id", "{id}",        "--plan", plan.dir,
                                   "--lcm-url", url,    "--reply-url", reply_url};
  // Each agent its own keys (docs/security.md), the robot world the master.
  std::vector<std::string> keying;
  if (key) {
    keying = {"--key-file", key_file};
    if (!fleet_of.external) {
      agent::write_agent_keys(*key, plan.plan.file, keys_dir);
      command.insert(command.end(), {"--key-file", keys_dir + "/agent-{id}.key"});
    }
  } else {
    keying = {"--insecure"};
    command.insert(command.end(), keying.begin(), keying.end());
  }
  if (!opt.journal_dir.empty()) command.insert(command.end(), {"--journal", opt.journal_dir});
  if (robots.any()) command.insert(command.end(), {"--motion", "lcm"});
  std::unique_ptr<AgentFleet> world;
  if (!robots.world_bin.empty()) {
    std::vector<std::string> w{robots.world_bin, "--plan", plan.dir, "--lcm-url", url, "--reply-url", reply_url};
    w.insert(w.end(), keying.begin(), keying.end());
    if (!robots.world_config.empty()) w.insert(w.end(), {"--config", robots.world_config});
    world = std::make_unique<AgentFleet>(w, 1);
    world->start();
  }
  AgentFleet processes(command, team.agents());
  if (fleet_of.external) {
    std::printf("waiting up to %.0f s for the %d agents of the plan on %s (started on the robots: robot.launch)\n",
                agent::kExternalReadyTimeout_s, team.agents(), url.c_str());
    std::fflush(stdout);
  } else {
    processes.start();
  }
  try {
    agent::MasterOptions mo;
    mo.tick = opt.tick, mo.loss = opt.loss, mo.loss_seed = opt.loss_seed, mo.rate = rate;
    mo.kills = opt.kills;
    mo.restarts = opt.restarts;
    mo.respawn = [&processes](int id) { processes.respawn(id, {"--rejoin"}); };
    mo.kill_agent = [&processes](int id) { processes.kill(id); };
    // Every agent process not running (AgentFleet keeps its status until it
    // is started again; the OC skips those it ended itself).
    if (!fleet_of.external)
      mo.ended = [&processes] {
        processes.poll();
        std::vector<std::pair<int, int>> out;
        for (const AgentProcess& p : processes.agents())
          if (!p.running) out.emplace_back(p.id, p.exit_status);
        return out;
      };
    if (wall) mo.clock = agent::ClockMode::kWall;
    mo.robots = robots.any();
    if (fleet_of.external) mo.ready_timeout_s = agent::kExternalReadyTimeout_s;
    agent::LockstepMaster master(team, fleet, digest, mo);
    const auto t0 = std::chrono::steady_clock::now();
    master.start(nullptr);
    const double ready_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    while (master.tick(nullptr)) {
    }
    agent::RunOutcome out = master.finish();
    // Where the time goes (wall of the ticks, and the agents' own CPU).
    const double wall_s = out.wall_ms / 1000.0, ticks = static_cast<double>(std::max<int64_t>(1, out.ticks));
    if (wall) {
      std::printf("over LCM on the wall clock at %g x: %lld control steps of the OC, %lld radio messages from the OC\n",
                  rate, static_cast<long long>(out.ticks), static_cast<long long>(out.messages));
      if (fleet_of.external) return out;
      processes.wait(5.0);
      processes.stop(2.0);
      for (const AgentProcess& p : processes.agents())  // stopped ones exit 0 (SIGTERM)
        if (p.exit_status != 0)
          throw RuntimeError("agent " + std::to_string(p.id), "exited with status " + std::to_string(p.exit_status));
      return out;
    }
    std::printf(
        "over LCM: %lld ticks, %lld radio messages = %.0f messages/s; agents ready after %.2f s; per tick %.3f ms "
        "of wall: publishing the tick %.3f ms, the OC's inbox %.3f ms, its role %.3f ms, waiting for the agents' "
        "replies %.3f ms (their control steps: %.3f ms of CPU summed over %d processes), the rest %.3f ms\n",
        static_cast<long long>(out.ticks), static_cast<long long>(out.messages),
        wall_s > 0 ? static_cast<double>(out.messages) / wall_s : 0.0, ready_s, out.wall_ms / ticks,
        master.publish_ms() / ticks, master.inbox_ms() / ticks, master.oc_ms() / ticks, master.wait_ms() / ticks,
        master.agents_step_ms() / ticks, team.agents(),
        (out.wall_ms - master.publish_ms() - master.inbox_ms() - master.oc_ms() - master.wait_ms()) / ticks);
    if (fleet_of.external) return out;
    processes.wait(5.0);  // they end by themselves on the last tick
    processes.stop(2.0);
    if (world) {
      world->wait(5.0);
      world->stop(2.0);
      if (world->agents()[0].exit_status != 0)
        throw RuntimeError("gather_world", "exited with status " + std::to_string(world->agents()[0].exit_status));
    }
    for (const AgentProcess& p : processes.agents()) {
      bool killed = false;
      for (const agent::Kill& k : opt.kills) killed = killed || k.agent == p.id;
      if (p.exit_status != 0 && !killed)
        throw RuntimeError("agent " + std::to_string(p.id), "exited with status " + std::to_string(p.exit_status));
    }
    return out;
  } catch (const RuntimeError&) {
    throw;
  } catch (const Error& e) {
    // An agent that refused the plan is bad input (its files differ);
    // anything else here happened while running.
    if (std::string(e.what()).find("refused the plan") != std::string::npos) throw;
    throw RuntimeError("", e.what());
  }
}

// One run with every agent in this process (on gather_world's robots: its
// child over a pipe).
agent::RunOutcome run_in_process(agent::TeamSetup& team, const agent::LoadedPlan& plan, agent::RunOptions opt,
                                 const Robots& robots) {
  if (robots.world_bin.empty()) return agent::TeamRunner(team, opt).run();
  std::vector<std::string> command{robots.world_bin, "--plan", plan.dir};
  if (!robots.world_config.empty()) command.insert(command.end(), {"--config", robots.world_config});
  agent::PipeWorld world(command, team.agents());
  opt.robots = &world;
  return agent::TeamRunner(team, opt).run();
}

}  // namespace

int keygen(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--key-id", "--agent", "--plan", "--master"}, {});
  const char* usage =
      "usage: gather keygen FILE [--key-id N]  |  gather keygen FILE --agent K --plan PLAN_DIR --master MASTER";
  if (args.positional().size() != 1) throw cli::UsageError(usage);
  const std::string path = args.positional()[0];
  if (args.has("--agent") || args.has("--plan") || args.has("--master")) {
    // An agent's keys: those of the links its plan gives it, from the master.
    for (const char* flag : {"--agent", "--plan", "--master"})
      if (!args.has(flag))
        throw cli::UsageError(std::string(flag) + " is needed with --agent, --plan and --master: " + usage);
    if (args.has("--key-id")) throw Error("--key-id", "an agent's key file takes the master's key id");
    const agent::FleetKey master = agent::load_fleet_key(args.get("--master"));
    const agent::LoadedPlan plan = agent::load_plan(args.get("--plan"));
    const int agents = plan.plan.file.agents.count();
    const int k = args.get_int(range::kKeygenAgent, 0);
    if (k >= agents)
      throw Error("--agent", std::to_string(k) + " is not in the plan (agents 0.." + std::to_string(agents - 1) + ")");
    const agent::KeyRing ring = agent::agent_keys_for(master, k, plan.plan.file);
    agent::write_key_ring(path, ring);
    std::printf(
        "agent %d's keys (%zu links, fleet key %d) -> %s (mode 0600; copy it to that robot only: "
        "docs/security.md)\n",
        k, ring.links.size(), ring.id, path.c_str());
    return 0;
  }
  const int id = args.get_int(range::kKeygenKeyId, 0);
  const agent::FleetKey key = agent::generate_fleet_key(id);
  agent::write_fleet_key(path, key);
  std::printf(
      "fleet master key %d -> %s (mode 0600; the OC's: each robot gets its own keys from it, gather keygen "
      "--agent: docs/security.md)\n",
      key.id, path.c_str());
  return 0;
}

int run(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--cycles",   "--seeds",        "--seed",    "--out",          "--tick",
                                 "--loss",     "--loss-seed",    "--lcm-url", "--reply-url",    "--agent-bin",
                                 "--rate",     "--clock",        "--kill",    "--repair",       "--silent-intervals",
                                 "--restart",  "--key-file",     "--robots",  "--world-config", "--world-bin",
                                 "--protocol", "--speed-factor", "--agents",  "--replay",       "--revoke"},
                 {"--lcm", "--insecure"});
  if (args.positional().size() != 1 || !args.has("--out"))
    throw cli::UsageError(
        "usage: gather run PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--tick DT] [--loss P] "
        "[--loss-seed N] [--kill ID@T[,ID@T...]] [--repair merge|none] [--silent-intervals K] [--restart "
        "ID@T[,ID@T...]] [--revoke ID@T[,ID@T...]] [--robots ideal|mrpt|external [--world-config YAML] [--world-bin "
        "FILE]] [--protocol "
        "ideal|robots] [--speed-factor F] "
        "[--lcm (--key-file F | "
        "--insecure) [--lcm-url URL] [--reply-url URL] [--agent-bin FILE] [--rate R] [--clock lockstep|wall] "
        "[--agents spawn|external]]");
  const bool over_lcm = args.on("--lcm");
  for (const char* flag :
       {"--lcm-url", "--reply-url", "--agent-bin", "--rate", "--clock", "--key-file", "--agents", "--replay"})
    if (args.has(flag) && !over_lcm) throw cli::UsageError(std::string(flag) + " needs --lcm");
  if (args.on("--insecure") && !over_lcm) throw cli::UsageError("--insecure needs --lcm");
  std::string lcm_url = args.get("--lcm-url", "");
  if (over_lcm && lcm_url.empty() && !args.has("--replay")) {
    // UDP multicast on the host's own network is not what a simulation wants.
    const char* netns = std::getenv("GATHER_NETNS");
    if (!netns || std::string(netns) != "1")
      throw cli::UsageError("--lcm sends UDP multicast: run it inside tools/netns-run, or give --lcm-url");
    lcm_url = agent::kHostFleetUrl;
  }
  const std::string robots_kind = args.get("--robots", "ideal");
  if (robots_kind != "ideal" && robots_kind != "mrpt" && robots_kind != "external")
    throw cli::UsageError(
        "--robots must be ideal (ideal bases), mrpt (gather_world's robots) or external (robots your drivers drive "
        "over LCM), got '" +
        robots_kind.substr(0, 40) + "'");
  for (const char* flag : {"--world-config", "--world-bin"})
    if (args.has(flag) && robots_kind != "mrpt") throw cli::UsageError(std::string(flag) + " needs --robots mrpt");
  Robots robots;
  robots.external = robots_kind == "external";
  if (robots.external && !args.on("--lcm"))
    throw cli::UsageError("--robots external needs --lcm (the robots' drivers speak the robot interface over LCM)");
  if (robots_kind == "mrpt") {
    robots.world_bin = find_world_binary(args.get("--world-bin", ""));
    if (robots.world_bin.empty())
      throw Error(args.has("--world-bin") ? "--world-bin" : "gather run --robots mrpt",
                  args.has("--world-bin") ? "'" + args.get("--world-bin") + "' is not an executable file"
                                          : "gather_world not found beside gather, in CMAKE_PREFIX_PATH or PATH");
    robots.world_config = args.get("--world-config", "");
  }
  const std::string clock = args.get("--clock", "lockstep");
  if (clock != "lockstep" && clock != "wall")
    throw cli::UsageError("--clock must be lockstep or wall, got '" + clock.substr(0, 40) + "'");
  bool wall_clock = clock == "wall";
  if (robots.external && !wall_clock)
    throw cli::UsageError("--robots external needs --clock wall (robots drive on their own clock, not on ticks)");
  // A recording of a wall-clock mission played back (--replay): the
  // mission's settings are the recording's (agent::replay_mission).
  Fleet fleet_of;
  std::optional<agent::Recording> recording;
  std::optional<agent::FleetKey> replay_key;
  if (args.has("--replay")) {
    for (const char* flag :
         {"--clock",     "--rate",    "--agents",   "--robots", "--cycles",           "--seed",        "--seeds",
          "--kill",      "--restart", "--revoke",   "--loss",   "--loss-seed",        "--agent-bin",   "--lcm-url",
          "--reply-url", "--tick",    "--protocol", "--repair", "--silent-intervals", "--speed-factor"})
      if (args.has(flag))
        throw cli::UsageError(std::string("--replay takes the mission's settings from the recording: no ") + flag);
    const std::vector<std::string> logs = agent::replay_logs(args.get("--replay"), "--replay");
    replay_key = agent::fleet_key_from_options(args.get("--key-file", ""), args.on("--insecure"), "gather run");
    recording = agent::read_recording(logs, replay_key);
    wall_clock = true;
  }
  const double rate = args.get_double(range::kRunRate, wall_clock ? 1.0 : 0.0);
  if (!(rate >= 0.0) || rate > 1e6) throw cli::UsageError("--rate must be >= 0 (0: as fast as the lockstep allows)");
  if (wall_clock && !(rate > 0.0))
    throw cli::UsageError("--rate must be > 0 with --clock wall (mission seconds per wall second)");
  const auto t_start = std::chrono::steady_clock::now();
  agent::LoadedPlan loaded = agent::load_plan(args.positional()[0]);
  // Ideal bases at a fraction of the team speed, the plan as it is (its
  // cycle period, its segments): what a team that holds only that pace
  // delivers, to set robots' results beside (docs/robots.md).
  if (args.has("--speed-factor")) {
    if (robots_kind != "ideal" || over_lcm)
      throw cli::UsageError("--speed-factor needs ideal bases in this process (not --robots or --lcm)");
    loaded.scenario.team.speed *= args.get_double(range::kRunSpeedFactor, 1.0);
  }
  agent::MissionParams params = agent::mission_params(loaded.scenario);
  params.cycles = args.get_int(range::kRunCycles, params.cycles);
  // The protocol's tuning for robots (mission::robot_protocol), by default
  // with robots; with ideal bases to compare with them.
  const std::string protocol = args.get("--protocol", robots_kind != "ideal" ? "robots" : "ideal");
  if (protocol != "ideal" && protocol != "robots")
    throw cli::UsageError("--protocol must be ideal or robots, got '" + protocol.substr(0, 40) + "'");
  if (protocol == "ideal" && robots_kind == "mrpt")
    throw cli::UsageError(
        "--protocol ideal needs ideal bases: gather_world's robots start where the robot protocol "
        "puts them (mission::team_start_poses)");
  if (protocol == "robots") params.protocol = mission::robot_protocol(params.protocol);
  const int seeds = args.get_int(range::kRunSeeds, 1);
  const int seed0 = recording ? static_cast<int>(recording->plan.params.seed)
                              : args.get_int(range::kRunSeed, static_cast<int>(params.seed));
  mission::check_goal_budget(loaded.scenario.mission.goals_per_request, params.cycles, seeds, loaded.scenario.path);
  agent::RunOptions opt;
  opt.tick = args.get_double(range::kRunTick, opt.tick);
  opt.loss = args.get_double(range::kRunLoss, opt.loss);
  opt.loss_seed = static_cast<uint64_t>(args.get_int(range::kRunLossSeed, 1));
  params.repair = mission::parse_repair_mode(args.get("--repair", "merge"), "--repair");
  params.silent_intervals = args.get_double(range::kRunSilentIntervals, params.silent_intervals);
  if (recording) {
    agent::recorded_params(*recording, params);
    opt.tick = recording->plan.tick, opt.loss = recording->plan.loss;  // (for the summary line)
  }

  opt.kills = agent::parse_kills(args.get("--kill", ""), static_cast<int>(loaded.plan.file.agents.size()), "--kill");
  opt.restarts =
      agent::parse_kills(args.get("--restart", ""), static_cast<int>(loaded.plan.file.agents.size()), "--restart");
  for (const agent::Kill& r : opt.restarts)
    for (const agent::Kill& k : opt.kills)
      if (r.agent == k.agent)
        throw cli::UsageError("--restart: agent " + std::to_string(r.agent) + " is also killed (--kill)");
  // The OC revokes these agents' keys (docs/security.md, "Revocation").
  for (const agent::Kill& r :
       agent::parse_kills(args.get("--revoke", ""), static_cast<int>(loaded.plan.file.agents.size()), "--revoke"))
    params.revoke.emplace_back(static_cast<int16_t>(r.agent), r.at);
  const std::string agents_kind = args.get("--agents", "spawn");
  if (agents_kind != "spawn" && agents_kind != "external")
    throw cli::UsageError(
        "--agents must be spawn (this process starts them) or external (they run on the robots: "
        "robot.launch), got '" +
        agents_kind.substr(0, 40) + "'");
  fleet_of.external = agents_kind == "external" || recording;  // a replay starts no agent either
  if (fleet_of.external && !recording && (!wall_clock || !robots.external))
    throw cli::UsageError("--agents external needs --robots external --clock wall (agents on real robots)");
  if (fleet_of.external && (!opt.kills.empty() || !opt.restarts.empty() || args.has("--agent-bin")))
    throw cli::UsageError("--agents external: this process starts no agent (no --kill, --restart, --agent-bin)");
  if (fleet_of.external && seeds != 1) throw cli::UsageError("--agents external runs one seed");
  if (!opt.restarts.empty() && wall_clock) throw cli::UsageError("--restart needs the lockstep clock");
  if (!opt.kills.empty() && wall_clock) throw cli::UsageError("--kill needs the lockstep clock");
  if (params.cycles < 1 || params.cycles > 100000) throw cli::UsageError("--cycles must be in 1..100000");
  if (seeds < 1 || seeds > 10000) throw cli::UsageError("--seeds must be in 1..10000");
  const std::string out = args.get("--out");
  std::filesystem::create_directories(out);
  // With restarts every agent journals what it carries (each run starts
  // its journals afresh).
  if (!opt.restarts.empty()) opt.journal_dir = (std::filesystem::path(out) / "journal").string();

  const mission::World world(loaded.scenario);
  agent::TeamSetup team(world, loaded.plan, params);
  const plan::PlanFile& pf = loaded.plan.file;
  agent::RunFiles files;
  double wall = 0.0, mission_s = 0.0, refresh = 0.0, per_cycle = 0.0, slowest = 1e300;
  int64_t messages = 0, ticks = 0;
  std::string agent_bin;
  uint64_t digest = 0;
  std::optional<agent::FleetKey> key;
  if (over_lcm) {
    if (!fleet_of.external) agent_bin = find_agent_binary(args.get("--agent-bin", ""));
    if (agent_bin.empty() && !fleet_of.external)
      throw Error(args.has("--agent-bin") ? "--agent-bin" : "gather run --lcm",
                  args.has("--agent-bin") ? "'" + args.get("--agent-bin") + "' is not an executable file"
                                          : "gather_agent not found beside gather, in CMAKE_PREFIX_PATH or PATH");
    digest = agent::plan_digest(loaded);
    key = recording ? replay_key
                    : agent::fleet_key_from_options(args.get("--key-file", ""), args.on("--insecure"), "gather run");
  }
  for (int k = 0; k < seeds; ++k) {
    team.params.seed = static_cast<unsigned>(seed0) + static_cast<unsigned>(k);
    const agent::RunOutcome r = recording ? agent::replay_mission(team, loaded, *recording, key)
                                : over_lcm
                                    ? run_over_lcm(team, loaded, digest, opt, rate, wall_clock, lcm_url,
                                                   args.get("--reply-url", agent::LcmFleet::reply_url_for(lcm_url)),
                                                   agent_bin, args.get("--key-file", ""), key,
                                                   (std::filesystem::path(out) / "keys").string(), robots, fleet_of)
                                    : run_in_process(team, loaded, opt, robots);
    if (!r.completed) throw RuntimeError(args.positional()[0], r.failure);
    if (over_lcm) {
      agent::AuthCounters all = r.oc_auth;
      for (const agent::AgentSummary& a : r.agents) all += a.auth;
      if (all.total() > 0)
        std::printf("seed %u: fleet messages dropped before decoding (the OC and every agent): %s; the OC alone: %s\n",
                    team.params.seed, agent::describe(all).c_str(), agent::describe(r.oc_auth).c_str());
    }
    if (r.closed_at_end > 0)
      std::fprintf(stderr, "seed %u: %lld goals still owed at the time limit (%.0f s): lost with their agents\n",
                   team.params.seed, static_cast<long long>(r.closed_at_end), r.end_s);
    for (const agent::AgentSummary& a : r.agents)
      if (!a.robot_fault.empty())
        std::fprintf(stderr, "seed %u: agent %d: %s (%lld faults)\n", team.params.seed, a.id, a.robot_fault.c_str(),
                     static_cast<long long>(a.robot.faults));
    files.add(pf, team.params, r);
    // The wall clock paces the whole run (to the last goal resolved), the
    // lockstep's figure is the requested cycles' time, as gather sim's.
    wall += r.wall_ms, mission_s += wall_clock ? r.end_s : r.result.mission_s;
    refresh += r.result.refresh_mean_s, per_cycle += r.result.goals_per_cycle;
    slowest = std::min(slowest, (wall_clock ? r.end_s : r.result.mission_s) * 1000.0 / r.wall_ms);
    messages += r.messages, ticks += r.ticks;
    for (const agent::Revocation& v : r.revoked)
      std::printf("seed %u: %s\n", team.params.seed, agent::describe(v).c_str());
    if (r.invalid_items > 0)
      std::printf(
          "seed %u: the OC refused %lld invalid items (acked, not taken: items naming no goal of the mission, or "
          "that their sender may not hand in, such as a claim of a goal no plan gave it)\n",
          team.params.seed, static_cast<long long>(r.invalid_items));
    if (!opt.kills.empty() || !opt.restarts.empty() || !r.declared_dead.empty()) {
      std::string dead;
      for (const auto& [a, at] : r.declared_dead)
        dead += (dead.empty() ? "" : ", ") + std::to_string(a) + " at " + std::to_string(static_cast<int>(at)) + " s";
      std::string restarted;
      for (const agent::Kill& rs : opt.restarts) {
        restarted += (restarted.empty() ? "" : ", ") + std::to_string(rs.agent) + " at " +
                     std::to_string(static_cast<int>(rs.at)) + " s";
        for (const auto& [a, n] : r.restored)
          if (a == rs.agent) restarted += " (" + std::to_string(n) + " measured goals carried, from its journal)";
      }
      std::printf(
          "seed %u: %s%sdeclared dead: %s; goals delivered %d, expired %d, dropped %d, lost with an agent %d "
          "(%lld declared lost and recovered later; %lld given up by one worker and measured by another)\n",
          team.params.seed, restarted.empty() ? "" : "restarted: ", restarted.empty() ? "" : (restarted + "; ").c_str(),
          dead.empty() ? "none" : dead.c_str(), r.result.delivered, r.result.expired, r.result.dropped,
          r.result.lost_with_agent, static_cast<long long>(r.recovered), static_cast<long long>(r.overridden));
    }
  }
  files.write(out);
  const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  std::printf(
      "%s Nc=%d Nw=%d: %d seeds x %d cycles of %.1f s, agent runtime %s (tick %.3f s%s); refresh "
      "%.1f s (est. %.1f), goals per cycle %.2f (est. %.2f); %lld ticks, %lld messages; run %.0f ms for %.0f s "
      "of mission = %.0fx real time (slowest seed %.0fx); total %.0f ms -> %s\n",
      pf.method.c_str(), pf.collectors, pf.workers, seeds, params.cycles, pf.cycle_period_s,
      over_lcm ? ("over LCM, " + std::to_string(pf.agents.size()) + " agent processes").c_str() : "in one process",
      opt.tick, opt.loss > 0 ? (", loss " + std::to_string(opt.loss)).c_str() : "", refresh / seeds, pf.est_refresh_s,
      per_cycle / seeds, pf.est_goals, static_cast<long long>(ticks), static_cast<long long>(messages), wall, mission_s,
      wall > 0 ? mission_s * 1000.0 / wall : 0.0, slowest, total_ms, out.c_str());
  return 0;
}

}  // namespace cmd
}  // namespace gather
