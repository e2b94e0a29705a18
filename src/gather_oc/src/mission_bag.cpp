// mission_bag PLAN_DIR --replay LOG[,LOG...] (--key-file F | --insecure) --out DIR
//             [--view-period S] [--frame-id F]
// A wall-clock mission recorded with lcm-logger on the robots' network (the
// fleet's URL and the replies' URL: docs/robots.md, "Recording what the
// fleet said") played back into DIR/mission.bag, the bag review.launch
// shows in RViz: the OC's role runs again on what the fleet said
// (agent::replay_mission, as gather run --replay) and the OC's views
// (MissionPublisher) are written into the bag at mission time, as
// mission.launch record:=true would have recorded them. No ROS master is
// needed. Also writes the mission's results (goals.csv, cycles.csv,
// summary.csv, agents.csv, mission.yaml), the same as gather run --replay.
// Exit status: 0 done; 1 the recording ends before the mission did, or the
// mission did not complete (the bag then holds it up to there); 2 bad input.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include <rosbag/bag.h>

#include "cli.hpp"
#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/runner/replay.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_oc/mission_publisher.hpp"

namespace {

constexpr const char* kUsage =
    "usage: mission_bag PLAN_DIR --replay LOG[,LOG...] (--key-file F | --insecure) --out DIR [--view-period S] "
    "[--frame-id F]";

int run(int argc, char** argv) {
  using namespace gather;
  cli::Args args(argc, argv, 1, {"--replay", "--key-file", "--out", "--view-period", "--frame-id"}, {"--insecure"});
  if (args.positional().size() != 1 || !args.has("--replay") || !args.has("--out")) throw cli::UsageError(kUsage);
  PublisherOptions po;
  po.view_period = args.get_double(range::kBagViewPeriod, 0.5);
  const std::vector<std::string> logs = agent::replay_logs(args.get("--replay"), "--replay");
  po.frame = args.get("--frame-id", "map");
  if (po.frame.empty()) throw cli::UsageError("--frame-id must not be empty");
  const std::optional<agent::FleetKey> key =
      agent::fleet_key_from_options(args.get("--key-file", ""), args.on("--insecure"), "mission_bag");
  const agent::Recording recording = agent::read_recording(logs, key);
  const agent::LoadedPlan loaded = agent::load_plan(args.positional()[0]);
  agent::MissionParams params = agent::mission_params(loaded.scenario);
  agent::recorded_params(recording, params);
  const mission::World world(loaded.scenario);
  agent::TeamSetup team(world, loaded.plan, params);

  const std::string out = args.get("--out");
  std::filesystem::create_directories(out);
  const std::string bag_path = out + "/mission.bag", active = bag_path + ".active";
  rosbag::Bag bag;
  try {
    bag.open(active, rosbag::bagmode::Write);
  } catch (const std::exception& e) {
    throw Error(active, std::string("cannot be written: ") + e.what());
  }
  bag.setCompression(rosbag::compression::LZ4);
  po.robots = recording.plan.robots;
  MissionPublisher pub(bag, team, loaded.scenario.grid, po);
  const double rate = recording.plan.rate;  // the recorded mission's pace, as its views said
  agent::ReplayObserver observer;
  double until = 0.0;
  observer.started = [&](agent::LockstepMaster& m) { pub.before_start(m); };
  observer.stepped = [&](agent::LockstepMaster& m) {
    pub.after_tick(m, rate);
    until = m.last_tick_time();
  };
  observer.ended = [&](agent::LockstepMaster& m, const agent::RunOutcome& o) {
    pub.finish(m, o.completed ? "done" : "failed", rate);
  };
  // The bag is kept whatever happens: it shows the mission up to where it ended.
  auto close_bag = [&] {
    bag.close();
    std::filesystem::rename(active, bag_path);
  };
  agent::RunOutcome result;
  try {
    std::printf("mission_bag: playing back %zu recording(s) of the fleet into %s\n", logs.size(), bag_path.c_str());
    std::fflush(stdout);
    result = agent::replay_mission(team, loaded, recording, key, observer);
  } catch (const RuntimeError& e) {
    close_bag();
    throw RuntimeError("", std::string(e.what()) + " (" + bag_path +
                               " holds the mission until t = " + std::to_string(static_cast<int>(until)) + " s)");
  } catch (...) {
    bag.close();
    std::filesystem::remove(active);
    throw;
  }
  const agent::RunSettings settings{"lcm, wall clock, played back", recording.plan.tick, rate, recording.plan.loss};
  agent::write_mission_yaml(out + "/mission.yaml", loaded, params, settings, result);
  close_bag();
  if (!result.completed)
    throw RuntimeError("", result.failure + " (" + bag_path + " holds the mission until t = " +
                               std::to_string(static_cast<int>(until)) + " s; " + out + "/mission.yaml)");
  agent::RunFiles files;
  files.add(loaded.plan.file, params, result);
  files.write(out);
  std::printf(
      "mission_bag: %s Nc=%d, %d cycles, %zu goals requested, %d delivered; refresh %.1f s, %.2f goals per cycle; "
      "%.0f s of mission -> %s (review: roslaunch gather_oc review.launch bag:=%s)\n",
      loaded.plan.file.method.c_str(), loaded.plan.file.collectors, params.cycles, result.result.goals.size(),
      result.result.delivered, result.result.refresh_mean_s, result.result.goals_per_cycle, result.end_s, out.c_str(),
      bag_path.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  try {
    return run(argc, argv);
  } catch (const gather::cli::UsageError& e) {
    std::fprintf(stderr, "mission_bag: %s\n", e.what());
    return 2;
  } catch (const gather::RuntimeError& e) {
    std::fprintf(stderr, "mission_bag: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mission_bag: %s\n", e.what());
    return 2;
  }
}
