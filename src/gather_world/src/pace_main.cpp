// gather_world_pace SCENARIO [--config WORLD_YAML] X Y [X Y ...]: how much
// of the team speed one MRPT robot of gather_world holds alone on a map.
// The robot starts at the OC and drives to each point in turn (one
// navigation command each, the goal tolerance of a worker's robot); for
// each leg it prints the shortest way's length (Fast Marching on the map),
// the time that takes at the team speed, the time the robot took, their
// ratio (its pace), how far it drove and how long it stood. The plan counts
// on the team speed: a team whose robots hold a pace of 0.8 delivers about
// what ideal bases at 0.8 x the speed do (gather run --speed-factor;
// docs/robots.md).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "gather_agent/motion/robot_base.hpp"
#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_world/mrpt_world.hpp"
#include "gather_world/world_params.hpp"

namespace {

constexpr const char* kUsage = "usage: gather_world_pace SCENARIO [--config WORLD_YAML] X Y [X Y ...]";
constexpr double kTick = 0.1;        // [s] the world's step, as gather run's
constexpr double kLongest = 3600.0;  // [s] a leg not done by then is reported as such
constexpr double kStill = 0.02;      // [m/s] slower than this counts as standing

double number(const char* s, const char* what) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (*s == '\0' || *end != '\0' || !std::isfinite(v))
    throw gather::Error("gather_world_pace",
                        std::string(what) + " must be a finite number, got '" + std::string(s).substr(0, 40) + "'");
  return v;
}

std::string point_text(gather::Point2 p) {
  char b[64];
  std::snprintf(b, sizeof b, "(%.2f, %.2f)", p.x, p.y);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gather;
  try {
    std::string scenario_path, config;
    std::vector<double> xy;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        std::printf("%s\n", kUsage);
        return 0;
      }
      if (a == "--config") {
        if (i + 1 >= argc) throw Error("gather_world_pace", "--config needs a file");
        config = argv[++i];
      } else if (scenario_path.empty()) {
        scenario_path = a;
      } else {
        xy.push_back(number(argv[i], xy.size() % 2 == 0 ? "X" : "Y"));
      }
    }
    if (scenario_path.empty() || xy.empty() || xy.size() % 2 != 0) {
      std::fprintf(stderr, "%s\n", kUsage);
      return 2;
    }
    const Scenario s = load_scenario(scenario_path);
    const world::WorldParams params = world::load_world_params(config);
    for (std::size_t j = 0; j + 1 < xy.size(); j += 2)
      if (!s.grid.is_free(s.grid.world_to_cell(Point2{xy[j], xy[j + 1]})))
        throw Error("gather_world_pace",
                    "point " + point_text(Point2{xy[j], xy[j + 1]}) + " is not on the free space of " + s.map_path);
    world::MrptWorld w(s.grid, {s.oc}, s.team.speed, s.team.radius, params);
    fmm::FastMarching fm(s.grid);
    const double tolerance = agent::RobotBaseParams{}.tolerance_m;
    std::vector<agent::RobotPose> poses;
    std::vector<agent::NavStatus> statuses;
    Point2 at = s.oc;
    int64_t tick = 0;
    double planned_sum = 0.0, took_sum = 0.0;
    std::printf("%-22s %9s %9s %9s %6s %9s %8s\n", "leg to [m]", "way [m]", "plan [s]", "took [s]", "pace", "drove [m]",
                "stood [s]");
    for (std::size_t j = 0; j + 1 < xy.size(); j += 2) {
      const Point2 to{xy[j], xy[j + 1]};
      const Cell c = s.grid.world_to_cell(to);
      fm.solve({fmm::Source::at_point(at)});
      const double way = fm.time(c);
      if (!(way < 1e18))
        throw Error("gather_world_pace", "point " + point_text(to) + " cannot be reached from where the robot stands");
      agent::NavCommand cmd;
      cmd.agent = 0, cmd.id = static_cast<int32_t>(j / 2 + 1), cmd.kind = agent::NavCommand::Kind::kGo, cmd.n = 1;
      cmd.points[0] = to, cmd.after[0] = way / s.team.speed, cmd.tolerance[0] = tolerance;
      const double t0 = static_cast<double>(tick) * kTick;
      double drove = 0.0, stood = 0.0, t = t0;
      agent::NavState state = agent::NavState::kActive;
      for (bool first = true; state == agent::NavState::kActive || state == agent::NavState::kBlocked;
           first = false, ++tick) {
        t = static_cast<double>(tick) * kTick;
        if (t - t0 > kLongest) break;
        w.step(tick, t, first ? std::vector<agent::NavCommand>{cmd} : std::vector<agent::NavCommand>{}, poses,
               statuses);
        const Point2 p = poses.at(0).at;
        drove += std::hypot(p.x - at.x, p.y - at.y);
        if (std::abs(poses[0].v) < kStill) stood += kTick;
        at = p;
        for (const agent::NavStatus& st : statuses)
          if (st.command == cmd.id) state = st.state;
      }
      const double took = t - t0, planned = way / s.team.speed;
      const char* end = state == agent::NavState::kReached  ? ""
                        : state == agent::NavState::kFailed ? "  FAILED"
                                                            : "  not there";
      char pace[16] = "-";  // a leg over in its first step (the point where the robot stands) has none
      if (took > 0.0) std::snprintf(pace, sizeof pace, "%.2f", planned / took);
      std::printf("(%8.2f, %8.2f)  %9.1f %9.1f %9.1f %6s %9.1f %8.1f%s\n", to.x, to.y, way, planned, took, pace, drove,
                  stood, end);
      if (state == agent::NavState::kReached) planned_sum += planned, took_sum += took;
    }
    if (took_sum > 0.0)
      std::printf("pace over the legs reached: %.2f of the team speed (%.2f m/s, top speed %.2f m/s)\n",
                  planned_sum / took_sum, s.team.speed, w.max_speed());
    return 0;
  } catch (const gather::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gather_world_pace: %s\n", e.what());
    return 2;
  }
}
