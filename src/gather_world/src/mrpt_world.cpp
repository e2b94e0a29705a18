// MrptWorld: the robots on MRPT (vehicle, reactive navigator, laser), their
// own global planner, the traffic rules between them (who makes way for
// whom), and the robot interface's messages. Over 400 lines because the
// robot, its navigator's interface, the traffic rules and the world step
// read the same state; MRPT's configuration is generated in
// navigator_config().
#include "gather_world/mrpt_world.hpp"

#include <unistd.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/kinematics/CVehicleSimul_DiffDriven.h>
#include <mrpt/kinematics/CVehicleVelCmd_DiffDriven.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/CPolygon.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <mrpt/nav/reactive/CRobot2NavInterface.h>
#include <mrpt/nav/reactive/TWaypoint.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/path/grid_astar.hpp"

namespace gather {
namespace world {
namespace {

using agent::NavCommand;
using agent::NavState;
using mrpt::math::TPose2D;
using Steady = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
// The top speed of a robot by default, over the scenario's team speed (the
// speed the plan counts on): a lone robot then holds about the team speed
// over a tour (gather_world_pace: 0.97-1.01), as a fleet is planned at what
// its robots average, not at their top speed (at which one holds 0.85-0.88:
// it slows in turns and near walls, takes corners wide, turns on the spot).
constexpr double kTopOverTeamSpeed = 1.15;
// [s] the vehicle's inner control period (CVehicleSimul_DiffDriven's firmware step).
constexpr double kFirmwarePeriod = 0.005;
// [m] targets between two waypoints count as reached this close (the
// robot heads for the next one earlier if it sees it: follow()).
constexpr double kPassTolerance = 0.25;
// [m] the global planner keeps its way this much further off the walls
// than it must where it can (the navigator slows down near them), except
// within kLooseEnds of a straight piece's ends.
constexpr double kComfort = 0.15;
constexpr double kLooseEnds = 0.3;
// [m] beyond its radius: the clearance of a point the robot is sent to.
constexpr double kFit = 0.01;
// [m] a waypoint the robot can get no closer to than its tolerance less
// this is one it cannot reach.
constexpr double kMinReach = 0.02;
// [m] a robot touches a wall once its disc reaches this far into it (a
// hair, for rounding).
constexpr double kContactSlack = 0.005;
// A target on the way that is not a waypoint of the command: a corner of
// the way (passed once the next one is in sight), or a point to pass a
// robot met head on at (keep_right).
constexpr int kCorner = -1;
constexpr int kPassing = -2;
// [m] a robot that got this far from where it last made progress makes
// progress (less is a robot rocking on the spot). Not the way left: a new
// command, a new way, or a target passed within kPassTolerance changes it
// by more than a robot standing still.
constexpr double kProgressStep = 0.4;
// [s] a robot without progress this long, another robot on its way ahead:
// one of them makes way; kHeadOnAfter where each is in the other's way.
constexpr double kYieldAfter = 3.0;
constexpr double kHeadOnAfter = 1.0;
// [s] after finding no spot to make way at, it looks again this much later.
constexpr double kAskAgain = 1.0;
// [m] how far along its way a robot looks for robots in it.
constexpr double kLookAhead = 2.0;
// [m] how much of the way of the robot given way to the one making way keeps off.
constexpr double kClearAhead = 6.0;
// [m] beyond the two radii: a robot this close to a way is in it; one
// making way keeps kKeepOff off it (the navigator passes a robot that
// leaves it less room only slowly, or not at all).
constexpr double kInWay = 0.2;
constexpr double kKeepOff = 0.4;
constexpr double kKeepOffTight = 0.25;  // where there is no room for kKeepOff (a corridor)
// [m] beyond the two radii: a spot to make way at is this clear of the other robots.
constexpr double kSpotGap = 0.1;
// [m] how far a driving robot may go to make way, and to back off when blocked.
constexpr double kAsideRange = 3.0;
constexpr double kBackOffRange = 1.0;
constexpr double kBackOffStep = 0.4;
// [m] how far from where it stopped an idle robot may go to make way (a
// courtesy: it stays about where its agent left it).
constexpr double kCourtesyRange = 1.0;
// [m] how close counts as arrived at a spot to make way at.
constexpr double kAsideTolerance = 0.15;
// [s] longest drive to such a spot, longest wait there for the other to pass.
constexpr double kAsideTimeout = 6.0;
constexpr double kHoldTimeout = 8.0;
// [m] a robot is past one that made way for it once the point this far
// along its way is further from that one than itself.
constexpr double kPassedAhead = 0.4;
// [rad] a robot whose way turns back further than this turns on the spot
// until within kTurnDone: the navigator's trajectories do not reach a
// target right behind (it would drive away from it, or back up all the way).
constexpr double kTurnStart = 1.75;
constexpr double kTurnDone = 0.5;
// [m] the point of its way the robot turns to: this far ahead.
constexpr double kTurnAim = 1.0;
// [m] a waypoint closer than this with nothing in between: the robot turns
// to it and drives straight there once within kDirectAligned [rad].
constexpr double kDirectRange = 1.0;
constexpr double kDirectAligned = 0.3;
// [m/s] its least speed on the way there (it slows down not to pass
// through its reach between two navigation steps).
constexpr double kCreep = 0.05;

// The vehicle, stepped an exact number of inner periods a world step:
// simulateOneTimeStep(dt) runs while its time <= start + dt, one inner step
// too many whenever the sum rounds down; half a period less is exact.
class Vehicle : public mrpt::kinematics::CVehicleSimul_DiffDriven {
 public:
  Vehicle() { m_firmware_control_period = kFirmwarePeriod; }
  void step(double dt) { simulateOneTimeStep(dt - 0.5 * m_firmware_control_period); }
};

// The navigator, quiet: no console, no log files, no timing tables.
class Navigator : public mrpt::nav::CReactiveNavigationSystem {
 public:
  explicit Navigator(mrpt::nav::CRobot2NavInterface& robot) : CReactiveNavigationSystem(robot, false, false) {
    setVerbosityLevel(mrpt::system::LVL_ERROR);
    logging_enable_console_output = false;
    m_timlog_delays.enable(false);
    m_navProfiler.enable(false);
    enableTimeLog(false);
  }
};

// MRPT's navigator configuration from the world's parameters: a disc robot
// with two families of forward trajectories (arcs, and turning towards the
// target), the full-evaluation holonomic method, and a score that prefers
// a clear way that ends near the target. No arcs backwards: with them a
// robot whose way starts behind it backs up all of it, and rocks back and
// forth near a target behind it; it turns on the spot instead (steer()).
// The PTGs' collision grids, which MRPT computes in seconds and caches on
// disk: one directory per configuration (its text and the robot's radius)
// under the temporary directory. A process that finds none fills a private
// one and renames it into place when done, so no process ever reads a
// cache another is still writing (worlds start side by side in tests and
// benchmarks).
class PtgCache {
 public:
  PtgCache(const std::string& config, double radius) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a
    char r[32];
    std::snprintf(r, sizeof r, "%.6f", radius);
    for (const char c : config + r) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    char name[48];
    std::snprintf(name, sizeof name, "gather_world_ptg_%016llx", static_cast<unsigned long long>(h));
    final_ = std::filesystem::temp_directory_path() / name;
    std::error_code ec;
    if (std::filesystem::is_directory(final_, ec)) {
      dir_ = final_.string();
      return;
    }
    const std::filesystem::path mine = final_.string() + ".tmp" + std::to_string(::getpid());
    std::filesystem::remove_all(mine, ec);
    std::filesystem::create_directories(mine);
    dir_ = mine.string();
    filling_ = true;
  }
  ~PtgCache() {
    std::error_code ec;
    if (filling_) std::filesystem::remove_all(dir_, ec);
  }
  const std::string& dir() const { return dir_; }
  // The grids are written: into place (another process may have been first).
  void keep() {
    if (!filling_) return;
    std::error_code ec;
    std::filesystem::rename(dir_, final_, ec);
    if (!ec) filling_ = false;
  }

 private:
  std::filesystem::path final_;
  std::string dir_;
  bool filling_ = false;
};

std::string navigator_config(const WorldParams& p, double v, double ref) {
  std::ostringstream s;
  s << "[CAbstractNavigator]\n"
    << "dist_to_target_for_sending_event = 0\n"
    // The world watches the robot's progress itself, across the commands
    // that replace each other (each would restart the navigator's alarms).
    << "alarm_seems_not_approaching_target_timeout = 1e9\n"
    << "dist_check_target_is_blocked = 0\n"
    << "hysteresis_check_target_is_blocked = 3\n"
    << "enable_time_profiler = false\n"
    << "[CWaypointsNavigator]\n"
    << "max_distance_to_allow_skip_waypoint = -1\n"
    << "min_timesteps_confirm_skip_waypoints = 1\n"
    << "waypoint_angle_tolerance = 5.0\n"
    << "multitarget_look_ahead = 0\n"
    << "[CAbstractPTGBasedReactive]\n"
    << "robotMax_V_mps = " << v << "\n"
    << "robotMax_W_degps = " << p.max_turn_rate << "\n"
    << "holonomic_method = CHolonomicFullEval\n"
    << "motion_decider_method = CMultiObjMotionOpt_Scalarization\n"
    << "ref_distance = " << ref << "\n"
    << "speedfilter_tau = 0\n"  // no blending with the measured (wall-clock) period
    << "secure_distance_start = 0.05\n"
    << "secure_distance_end = 0.20\n"
    << "use_delays_model = false\n"  // it extrapolates with timestamps
    << "max_distance_predicted_actual_path = 0.15\n"
    << "min_normalized_free_space_for_ptg_continuation = 0.2\n"
    << "enable_obstacle_filtering = false\n"
    << "evaluate_clearance = false\n"
    << "[CHolonomicFullEval]\n"
    << "factorWeights = [0.25 0.1 1 0.05 0.5 1 1]\n"
    << "factorNormalizeOrNot = [0 0 0 0 1 1 0]\n"
    << "TOO_CLOSE_OBSTACLE = 0.10\n"
    << "TARGET_SLOW_APPROACHING_DISTANCE = 0.10\n"
    << "OBSTACLE_SLOW_DOWN_DISTANCE = 0.10\n"
    << "HYSTERESIS_SECTOR_COUNT = 5\n"
    << "LOG_SCORE_MATRIX = false\n"
    << "clearance_threshold_ratio = 0.05\n"
    << "gap_width_ratio_threshold = 0.20\n"
    << "PHASE_COUNT = 3\n"
    << "PHASE1_FACTORS = [6]\nPHASE1_THRESHOLD = 0.5\n"
    << "PHASE2_FACTORS = [4]\nPHASE2_THRESHOLD = 0.7\n"
    << "PHASE3_FACTORS = [0 2]\nPHASE3_THRESHOLD = 0.7\n"
    << "[CMultiObjectiveMotionOptimizerBase]\n"
    // clear: the way is free up to the target (else how far it is free)
    << "score1_name = clear\n"
    << "score1_formula = var d := max(0, target_d_norm - move_cur_d); if(collision_free_distance > d + 0.05, 1.0, "
       "collision_free_distance)\n"
    // near: the trajectory passes close to the target
    << "score2_name = near\n"
    << "score2_formula = 1 / (1 + dist_eucl_min^2)\n"
    // steady: keep the previous choice
    << "score3_name = steady\n"
    << "score3_formula = hysteresis\n"
    // aimed: the trajectory's direction against the target's, circular
    << "score4_name = aimed\n"
    << "score4_formula = var k := abs(target_k - move_k); if (k > num_paths / 2) { k := num_paths - k; }; "
       "exp(-k / (num_paths / 10.0))\n"
    << "score5_name = family\n"
    << "score5_formula = ptg_priority\n"
    << "scores_to_normalize =\n"
    << "[CMultiObjMotionOpt_Scalarization]\n"
    << "scalar_score_formula = family * (0.5 * clear + 8.0 * near + 0.1 * steady + 0.2 * aimed)\n"
    << "[CReactiveNavigationSystem]\n"
    << "min_obstacles_height = 0.0\nmax_obstacles_height = 10.0\n"
    << "RobotModel_shape2D_xs = 0.2 0 -0.2 0\nRobotModel_shape2D_ys = 0 0.2 0 -0.2\n"  // replaced by the disc
    << "PTG_COUNT = 2\n";
  const char* types[2] = {"CPTG_DiffDrive_C", "CPTG_DiffDrive_alpha"};
  for (int k = 0; k < 2; ++k)
    s << "PTG" << k << "_Type = " << types[k] << "\n"
      << "PTG" << k << "_resolution = 0.05\n"
      << "PTG" << k << "_refDistance = " << ref << "\n"
      << "PTG" << k << "_num_paths = " << p.paths << "\n"
      << "PTG" << k << "_v_max_mps = " << v << "\n"
      << "PTG" << k << "_w_max_dps = " << p.max_turn_rate << "\n"
      << "PTG" << k << "_score_priority = 1.0\n";
  s << "PTG0_K = 1.0\n"
    << "PTG1_cte_a0v_deg = 57\nPTG1_cte_a0w_deg = 57\n";
  return s.str();
}

}  // namespace

class MrptWorld::Impl {
 public:
  struct Robot;

  // The navigator's view of one robot.
  class Interface : public mrpt::nav::CRobot2NavInterface {
   public:
    Interface(Impl& world, Robot& robot) : w_(world), r_(robot) { setVerbosityLevel(mrpt::system::LVL_ERROR); }
    bool getCurrentPoseAndSpeeds(TPose2D& pose, mrpt::math::TTwist2D& vel, mrpt::system::TTimeStamp& stamp,
                                 TPose2D& odometry, std::string& frame) override {
      pose = r_.veh->getCurrentGTPose();
      vel = r_.veh->getCurrentGTVel();
      odometry = r_.veh->getCurrentOdometricPose();
      stamp = mrpt::Clock::now();
      frame = "map";
      return true;
    }
    bool changeSpeeds(const mrpt::kinematics::CVehicleVelCmd& cmd) override {
      r_.veh->sendVelCmd(cmd);
      r_.last_cmd = w_.t_;
      return true;
    }
    bool changeSpeedsNOP() override {
      r_.last_cmd = w_.t_;
      return true;
    }
    bool stop(bool) override {
      mrpt::kinematics::CVehicleVelCmd_DiffDriven c;
      c.setToStop();
      r_.veh->sendVelCmd(c);
      r_.last_cmd = w_.t_;
      return true;
    }
    mrpt::kinematics::CVehicleVelCmd::Ptr getStopCmd() override {
      auto c = std::make_shared<mrpt::kinematics::CVehicleVelCmd_DiffDriven>();
      c->setToStop();
      return c;
    }
    mrpt::kinematics::CVehicleVelCmd::Ptr getEmergencyStopCmd() override { return getStopCmd(); }
    bool startWatchdog(float ms) override {
      r_.watchdog = ms * 1e-3, r_.last_cmd = w_.t_;
      return true;
    }
    bool stopWatchdog() override {
      r_.watchdog = -1;
      return true;
    }
    bool senseObstacles(mrpt::maps::CSimplePointsMap& obstacles, mrpt::system::TTimeStamp& stamp) override {
      w_.laser(r_, obstacles);
      stamp = mrpt::Clock::now();
      return true;
    }
    // The world's clock, not the default wall-clock timer.
    double getNavigationTime() override { return w_.t_ - t0_; }
    void resetNavigationTimer() override { t0_ = w_.t_; }
    void sendNavigationStartEvent() override {}
    void sendNavigationEndEvent() override { r_.nav_ended = true; }
    void sendWaypointReachedEvent(int index, bool) override { w_.target_reached(r_, index); }
    void sendNewWaypointTargetEvent(int) override {}
    void sendNavigationEndDueToErrorEvent() override { r_.nav_error = true; }
    // Its alarms are off (the world watches the progress): nothing to say.
    void sendWaySeemsBlockedEvent() override {}
    void sendApparentCollisionEvent() override {}
    void sendCannotGetCloserToBlockedTargetEvent() override {}

   private:
    Impl& w_;
    Robot& r_;
    double t0_ = 0.0;
  };

  // What a robot's wheels are doing: following its command's way, driving
  // to a spot to make way for another robot or to back off from a block,
  // or standing there until the other has passed.
  enum class Move { kRoute, kAside, kHold };

  struct Robot {
    int id = 0;
    // Declaration order: the navigator goes first (its destructor stops the
    // robot through the interface, which drives the vehicle).
    std::unique_ptr<Vehicle> veh;
    std::unique_ptr<Interface> iface;
    std::unique_ptr<Navigator> nav;
    NavCommand cmd;
    bool has_cmd = false;
    NavState state = NavState::kIdle;
    int reached = 0;                             // waypoints of the command reached
    double reached_at[agent::kMaxNavWaypoints];  // [s]
    int fail_at = -1;                            // a waypoint its planner found no way to (-1: none)
    // The way: targets for the navigator (the waypoint each is, or kCorner,
    // kPassing), how close counts, their arc positions [m], the first not
    // yet reached, and the first of the sequence the navigator was given.
    std::vector<Point2> targets;
    std::vector<int> target_waypoint;
    std::vector<double> target_reach;  // [m] counted reached this close
    std::vector<double> target_arc;
    Point2 way_from;  // where the way begins
    std::size_t next = 0, issued_from = 0;
    bool nav_ended = false, nav_error = false;
    // Progress, over the commands that replace each other (a robot stuck
    // is stuck whatever its agent asks next): where and when it last made
    // progress, when it last tried a new way, when it may next ask another
    // robot for way.
    Point2 progress_from;
    double progress_at = 0.0, retried_at = -1e9, ask_at = 0.0;
    Move move = Move::kRoute;
    int make_way_for = -1;  // the robot it stands aside for (-1: none, a back-off)
    Point2 spot;            // where it drives aside to
    bool turning = false;   // on the spot, towards its way (steer())
    double move_until = 0.0;
    Point2 home;  // where it stopped: an idle robot makes way kCourtesyRange around it
    double next_nav = 0.0;
    double watchdog = -1.0, last_cmd = 0.0;
    bool touching = false;
    RobotTally tally;
    // Its last scan (for views): where it was taken, when, each ray's range.
    TPose2D scan_pose;
    double scan_t = -1.0;
    std::vector<float> ranges;
  };

  Impl(const OccupancyGrid& map, const std::vector<Point2>& starts, double team_speed, double team_radius,
       const WorldParams& params)
      : params_(params),
        map_(map),
        radius_(params.radius > 0 ? params.radius : team_radius),
        v_(params.max_speed > 0 ? params.max_speed : kTopOverTeamSpeed * team_speed),
        clearance_(map) {
    check_params(params, "world params");
    if (!(radius_ > 0) || !(v_ > 0)) throw Error("world params", "the robots need a radius and a speed > 0");
    // MRPT's clock is the world's from here on (process-wide: one world a
    // process), before any navigator exists.
    epoch_ = mrpt::Clock::fromDouble(1.0e9);
    mrpt::Clock::setSimulatedTime(epoch_);
    mrpt::Clock::setActiveClock(mrpt::Clock::Simulated);
    // The laser's map: MRPT stores the probability of a cell being free;
    // anything not free (walls, unknown) stops a ray.
    const GridFrame& f = map.frame();
    laser_map_.setSize(f.origin.x, f.origin.x + f.width * f.resolution, f.origin.y,
                       f.origin.y + f.height * f.resolution, static_cast<float>(f.resolution), 1.0f);
    for (int r = 0; r < f.height; ++r)
      for (int c = 0; c < f.width; ++c) laser_map_.setCell(c, r, map.free_mask()[map.index(Cell{r, c})] ? 1.0f : 0.0f);
    // The global planner's maps: cells a disc of the robot fits on, and
    // those with room to spare, where it drives at speed.
    const double keep = params.clearance > 0 ? params.clearance : radius_ + 0.05;
    roomy_ = Mask(f, 0), comfy_ = Mask(f, 0);
    comfy_keep_ = keep + kComfort;
    for (std::size_t i = 0; i < map.size(); ++i) {
      roomy_[i] = map.free_mask()[i] && clearance_.values()[i] >= keep ? 1 : 0;
      comfy_[i] = roomy_[i] && clearance_.values()[i] >= comfy_keep_ ? 1 : 0;
    }
    planner_ = std::make_unique<GridAStar>(map_, roomy_);
    comfy_planner_ = std::make_unique<GridAStar>(map_, comfy_);
    label(roomy_, roomy_part_);
    label(comfy_, comfy_part_);
    cells_.reserve(static_cast<std::size_t>(4 * (f.width + f.height)));

    const double ref = std::min(params.ref_distance, 20.0);
    const std::string config_text = navigator_config(params, v_, ref);
    mrpt::config::CConfigFileMemory config(config_text);
    PtgCache cache(config_text, radius_);
    for (std::size_t k = 0; k < starts.size(); ++k) {
      auto r = std::make_unique<Robot>();
      r->id = static_cast<int>(k);
      r->veh = std::make_unique<Vehicle>();
      r->veh->setDelayModelParams(params.response_time, 0.0);
      const TPose2D start(starts[k].x, starts[k].y, 0.0);
      r->veh->setCurrentGTPose(start);
      r->veh->setCurrentOdometricPose(start);
      r->iface = std::make_unique<Interface>(*this, *r);
      r->nav = std::make_unique<Navigator>(*r->iface);
      r->nav->logRegisterCallback(
          [](std::string_view, mrpt::system::VerbosityLevel, std::string_view, mrpt::Clock::time_point) {});
      try {
        r->nav->loadConfigFile(config);
        mrpt::math::CPolygon disc;  // an octagon around the disc
        const double rc = radius_ / std::cos(kPi / 8);
        for (int a = 0; a < 8; ++a) disc.AddVertex(rc * std::cos(a * kPi / 4), rc * std::sin(a * kPi / 4));
        r->nav->changeRobotShape(disc);
        r->nav->params_abstract_ptg_navigator.ptg_cache_files_directory = cache.dir();
        r->nav->initialize();
      } catch (const std::exception& e) {
        std::string what = e.what();
        what = what.substr(0, what.find('\n'));
        throw Error("gather_world (internal error)", "MRPT's navigator refused its configuration: " + what);
      }
      r->home = starts[k];
      r->next_nav = params.nav_period * static_cast<double>(k % 4) / 4.0;  // spread over a period
      robots_.push_back(std::move(r));
    }
    cache.keep();
  }

  ~Impl() { robots_.clear(); }  // navigators first, while the world they call is whole

  // --- the robot's own global planner --------------------------------------

  // Numbers the 4-connected parts of `cells` (those A* may join: it takes
  // no diagonal step past a blocked corner) into `part` (-1 off them): a
  // search between two parts would visit all of one before it fails.
  void label(const Mask& cells, std::vector<int32_t>& part) const {
    part.assign(cells.size(), -1);
    std::vector<Cell> stack;
    int32_t next = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (!cells[i] || part[i] >= 0) continue;
      part[i] = next;
      stack.push_back(map_.cell(i));
      while (!stack.empty()) {
        const Cell c = stack.back();
        stack.pop_back();
        for (const Cell n :
             {Cell{c.row + 1, c.col}, Cell{c.row - 1, c.col}, Cell{c.row, c.col + 1}, Cell{c.row, c.col - 1}}) {
          if (!map_.contains(n)) continue;
          const std::size_t k = map_.index(n);
          if (cells[k] && part[k] < 0) part[k] = next, stack.push_back(n);
        }
      }
      ++next;
    }
  }

  bool joined(const std::vector<int32_t>& part, Cell a, Cell b) const {
    return a.row >= 0 && b.row >= 0 && part[map_.index(a)] >= 0 && part[map_.index(a)] == part[map_.index(b)];
  }

  // The nearest cell of `lanes` to `p` (p's own cell if it is one) within
  // 1 m, in a straight line through free cells (not across a wall); {-1, -1}
  // when there is none.
  Cell lane_cell(const Mask& lanes, Point2 p) const {
    const Cell c = map_.world_to_cell(p);
    if (map_.contains(c) && lanes[map_.index(c)]) return c;
    const int rings = static_cast<int>(std::ceil(1.0 / map_.resolution()));
    for (int k = 1; k <= rings; ++k) {
      Cell best{-1, -1};
      long best_d = -1;
      for (int dr = -k; dr <= k; ++dr)
        for (int dc = -k; dc <= k; ++dc) {
          if (std::max(std::abs(dr), std::abs(dc)) != k) continue;
          const Cell n{c.row + dr, c.col + dc};
          const long d = static_cast<long>(dr) * dr + static_cast<long>(dc) * dc;
          if (map_.contains(n) && lanes[map_.index(n)] && (best_d < 0 || d < best_d) &&
              sight(map_.free_mask(), p, map_.cell_center(n), 0.0))
            best = n, best_d = d;
        }
      if (best_d >= 0) return best;
    }
    return Cell{-1, -1};
  }

  // Whether the straight line a-b keeps to cells of `lanes` (a Mask, or the
  // map's free mask), or of the roomy ones within `loose` [m] of its ends.
  template <class Lanes>
  bool sight(const Lanes& lanes, Point2 a, Point2 b, double loose) const {
    const double len = distance(a, b);
    const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * map_.resolution()))));
    for (int i = 0; i <= n; ++i) {
      const double s = len * i / n;
      const Cell c = map_.world_to_cell(Point2{a.x + (b.x - a.x) * i / n, a.y + (b.y - a.y) * i / n});
      if (!map_.contains(c)) return false;
      const std::size_t k = map_.index(c);
      if (!lanes[k] && !(roomy_[k] && (s < loose || len - s < loose))) return false;
    }
    return true;
  }

  // Targets to `p` (the last the waypoint `waypoint`, counted reached
  // within `reach`; kCorner for a corner of the way), none further than
  // max_leg apart.
  void add_target(Robot& r, Point2 p, int waypoint, double reach = kPassTolerance) {
    const Point2 from =
        r.targets.empty() ? Point2{r.veh->getCurrentGTPose().x, r.veh->getCurrentGTPose().y} : r.targets.back();
    const double len = std::hypot(p.x - from.x, p.y - from.y);
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / params_.max_leg)));
    for (int k = 1; k <= pieces; ++k) {
      const Point2 q{from.x + (p.x - from.x) * k / pieces, from.y + (p.y - from.y) * k / pieces};
      const double arc = (r.target_arc.empty() ? 0.0 : r.target_arc.back()) + len / pieces;
      r.targets.push_back(k == pieces ? p : q);
      r.target_waypoint.push_back(k == pieces ? waypoint : kCorner);
      r.target_reach.push_back(k == pieces ? reach : kPassTolerance);
      r.target_arc.push_back(arc);
    }
  }

  // Where the robot goes for waypoint `p` of tolerance `tolerance`: p, or,
  // where its disc does not fit, the nearest point within the tolerance
  // where it does, counted reached within what is left of the tolerance
  // (`reach`: the waypoint's own is kept). False when none leaves kMinReach.
  bool approach(Point2 p, double tolerance, Point2& at, double& reach) const {
    const double fit = radius_ + kFit;
    if (!hits_wall(p, fit)) {
      at = p, reach = tolerance;
      return true;
    }
    const Cell c = map_.world_to_cell(p);
    const int k = static_cast<int>(std::ceil(tolerance / map_.resolution()));
    double best = tolerance - kMinReach;
    bool found = false;
    for (int dr = -k; dr <= k; ++dr)
      for (int dc = -k; dc <= k; ++dc) {
        const Cell n{c.row + dr, c.col + dc};
        if (!map_.contains(n)) continue;
        const Point2 q = map_.cell_center(n);
        const double d = distance(p, q);
        if (d <= best && !hits_wall(q, fit)) best = d, at = q, found = true;
      }
    reach = tolerance - best;
    return found;
  }

  // The way from where the robot is through waypoints `first`.. of its
  // command: A* on the cells it fits on between two of them, kept only where
  // a straight line would leave them. A waypoint it finds no way to ends
  // the way (fail_at).
  void plan(Robot& r, int first) {
    // Through the other robots; around those on that way, if there is a
    // way around (a search that finds none visits every cell it can reach:
    // only when it may pay), else through (they move, or make way).
    plan_way(r, first);
    if (r.fail_at >= 0 || !block_others(r)) return;
    std::swap(r.targets, spare_targets_), std::swap(r.target_waypoint, spare_waypoint_);
    std::swap(r.target_reach, spare_reach_), std::swap(r.target_arc, spare_arc_);
    plan_way(r, first);
    for (std::size_t i : blocked_) roomy_[i] = 1, comfy_[i] = clearance_.values()[i] >= comfy_keep_;
    blocked_.clear();
    if (r.fail_at < 0) return;
    std::swap(r.targets, spare_targets_), std::swap(r.target_waypoint, spare_waypoint_);
    std::swap(r.target_reach, spare_reach_), std::swap(r.target_arc, spare_arc_);
    r.fail_at = -1, r.next = 0;
  }

  // Marks the cells around each other robot on the robot's way as not
  // roomy; false when there is none. Not one in a
  // passage too narrow to pass it (a door, a corridor): the way around it
  // is long if there is one, it makes way instead.
  bool block_others(const Robot& r) {
    const int k = static_cast<int>(std::ceil(2.0 * radius_ / map_.resolution()));
    const Point2 self = position(r);
    way_ahead(r, std::numeric_limits<double>::infinity(), way_);
    for (const auto& o : robots_) {
      const Point2 q = position(*o);
      if (o->id == r.id || distance_to_way(q, way_) >= 2 * radius_ + kInWay) continue;
      if (distance(q, self) < 3.0 * radius_) continue;  // touching: not in its way, it is in it
      const Cell c = map_.world_to_cell(q);
      if (clearance_.at(c) < 4.0 * radius_) continue;
      for (int dr = -k; dr <= k; ++dr)
        for (int dc = -k; dc <= k; ++dc) {
          const Cell n{c.row + dr, c.col + dc};
          if (dr * dr + dc * dc > k * k || !map_.contains(n)) continue;
          const std::size_t i = map_.index(n);
          if (roomy_[i]) roomy_[i] = comfy_[i] = 0, blocked_.push_back(i);
        }
    }
    return !blocked_.empty();
  }

  void plan_way(Robot& r, int first) {
    ++r.tally.replans;
    r.targets.clear(), r.target_waypoint.clear(), r.target_reach.clear(), r.target_arc.clear();
    r.next = 0, r.fail_at = -1;
    const TPose2D at = r.veh->getCurrentGTPose();
    Point2 from{at.x, at.y};
    r.way_from = from;
    for (int k = first; k < r.cmd.n; ++k) {
      Point2 to;
      double reach = 0.0;
      if (!approach(r.cmd.points[k], r.cmd.tolerance[k], to, reach)) {
        r.fail_at = k;
        return;
      }
      // On the cells with room to spare, near the ends on any it fits on;
      // else on any.
      const Mask* lanes = &comfy_;
      Cell a = lane_cell(comfy_, from), b = lane_cell(comfy_, to);
      if (!joined(comfy_part_, a, b) || !comfy_planner_->find(a, b, cells_)) {
        lanes = &roomy_;
        a = lane_cell(roomy_, from), b = lane_cell(roomy_, to);
        if (!joined(roomy_part_, a, b) || !planner_->find(a, b, cells_)) {
          r.fail_at = k;
          return;
        }
      }
      Point2 anchor = from;
      for (std::size_t j = 0; j < cells_.size(); ++j) {
        const Point2 next = j + 1 < cells_.size() ? map_.cell_center(cells_[j + 1]) : to;
        if (j > 0 && !sight(*lanes, anchor, next, kLooseEnds))
          anchor = map_.cell_center(cells_[j]), add_target(r, anchor, kCorner);
      }
      add_target(r, to, k, reach);
      from = to;
    }
  }

  // --- the command ----------------------------------------------------------

  static bool driving(const Robot& r) { return r.state == NavState::kActive || r.state == NavState::kBlocked; }

  static Point2 position(const Robot& r) {
    const TPose2D g = r.veh->getCurrentGTPose();
    return Point2{g.x, g.y};
  }

  // [m] the way left: to its next target, then along the targets.
  static double way_left(const Robot& r) {
    if (r.next >= r.targets.size()) return 0.0;
    return distance(position(r), r.targets[r.next]) + r.target_arc.back() - r.target_arc[r.next];
  }

  // Hands the navigator the targets from r.next on.
  void issue(Robot& r) {
    r.issued_from = r.next;
    r.nav_ended = r.nav_error = false;
    if (r.next >= r.targets.size()) {
      r.nav->cancel();
      return;
    }
    mrpt::nav::TWaypointSequence seq;
    for (std::size_t k = r.next; k < r.targets.size(); ++k) {
      seq.waypoints.emplace_back(r.targets[k].x, r.targets[k].y, r.target_reach[k], false);
    }
    seq.waypoints.back().speed_ratio = 0.3;
    r.nav->navigateWaypoints(seq);
  }

  void target_reached(Robot& r, int index) {
    if (r.move == Move::kAside) {  // at the spot it makes way at
      hold(r);
      return;
    }
    if (r.move != Move::kRoute) return;
    const std::size_t k = r.issued_from + static_cast<std::size_t>(std::max(0, index));
    if (k < r.next || k >= r.targets.size()) return;
    r.next = k + 1;
    const int w = r.target_waypoint[k];
    if (w >= 0 && w + 1 > r.reached) {
      for (int i = r.reached; i <= w; ++i) r.reached_at[i] = t_;
      r.reached = w + 1;
      progress(r);
    }
  }

  void progress(Robot& r) {
    r.progress_from = position(r), r.progress_at = t_;
    if (r.state == NavState::kBlocked) r.state = NavState::kActive;
  }

  void take(const NavCommand& c) {
    if (c.agent < 0 || c.agent >= static_cast<int>(robots_.size())) return;
    Robot& r = *robots_[static_cast<std::size_t>(c.agent)];
    if (r.has_cmd && c.id == r.cmd.id) return;  // a repeat
    const bool was_driving = driving(r);
    if (was_driving && r.fail_at < 0 && same_rest(r, c)) {
      // The rest of the way it drives (an agent deciding again sends the
      // same waypoints under a new id): it drives on, waypoints counted anew.
      for (int& w : r.target_waypoint)
        if (w >= 0) w = w >= r.reached ? w - r.reached : kCorner;
      r.cmd = c, r.reached = 0;
      return;
    }
    r.cmd = c, r.has_cmd = true;
    r.reached = 0;
    if (c.kind == NavCommand::Kind::kStop || c.n == 0) {
      r.targets.clear(), r.target_waypoint.clear(), r.target_reach.clear(), r.target_arc.clear(), r.next = 0;
      r.move = Move::kRoute, r.make_way_for = -1;  // it stops making way too
      park(r, NavState::kIdle);
      return;
    }
    // A command that replaces one under way keeps the progress clock: the
    // robot is as stuck as it was (its agent may send a new one every few
    // seconds while it stands).
    if (!was_driving) {
      r.state = NavState::kActive;
      progress(r);
      r.ask_at = t_;
    }
    plan(r, 0);
    if (r.targets.empty() && r.fail_at >= 0) {
      fail(r);
      return;
    }
    if (r.move == Move::kRoute) issue(r);  // else once it has made way
  }

  // Whether command `c` is the waypoints robot r has yet to reach of its own.
  static bool same_rest(const Robot& r, const NavCommand& c) {
    if (c.kind != NavCommand::Kind::kGo || c.n != r.cmd.n - r.reached) return false;
    for (int k = 0; k < c.n; ++k) {
      const int o = k + r.reached;
      if (c.points[k].x != r.cmd.points[o].x || c.points[k].y != r.cmd.points[o].y ||
          c.tolerance[k] != r.cmd.tolerance[o])
        return false;
    }
    return true;
  }

  // It stops, and stays about there (home) until told otherwise.
  void park(Robot& r, NavState state) {
    r.state = state;
    r.nav->cancel();
    r.iface->stop(false);
    r.home = position(r);
  }

  void fail(Robot& r) {
    ++r.tally.failed;
    r.move = Move::kRoute, r.make_way_for = -1;
    park(r, NavState::kFailed);
  }

  // Whether the robot at `at` may head past its next target: a corner, or
  // a point to pass another robot at that it is past already (nearer the
  // target after it).
  static bool passable(const Robot& r, Point2 at) {
    const int w = r.target_waypoint[r.next];
    const Point2 after = r.targets[r.next + 1];
    return w == kCorner || (w == kPassing && distance(at, after) < distance(r.targets[r.next], after));
  }

  // After its navigation step: the end of the way, progress or the lack of
  // it (BLOCKED, another way, FAILED), making way.
  void follow(Robot& r) {
    if (r.move != Move::kRoute) manoeuvre(r);
    if (!driving(r)) return;
    if (r.move == Move::kRoute) {
      const bool error = r.nav_error || r.nav->getCurrentState() == mrpt::nav::CAbstractNavigator::NAV_ERROR;
      if (r.next >= r.targets.size() && (r.nav_ended || !error)) {
        if (r.fail_at >= 0)
          fail(r);
        else if (r.reached >= r.cmd.n)
          park(r, NavState::kReached);
        return;
      }
      // Past targets on the way once it sees the one after (a corner it
      // need not touch), as long as that one is within max_leg.
      const Point2 at = position(r);
      const std::size_t next = r.next;
      while (r.next + 1 < r.targets.size() && passable(r, at) &&
             distance(at, r.targets[r.next + 1]) <= params_.max_leg &&
             sight(comfy_, at, r.targets[r.next + 1], kLooseEnds))
        ++r.next;
      if (error || r.next != next) {  // the rest of the way (again, if the navigator stopped)
        r.nav->resetNavError();
        issue(r);
      }
    }
    if (distance(position(r), r.progress_from) >= kProgressStep) progress(r);
    const double still = t_ - r.progress_at;
    if (still > params_.give_up_after) {
      r.fail_at = r.reached;
      fail(r);
      return;
    }
    if (still > params_.blocked_after && r.state == NavState::kActive) {
      r.state = NavState::kBlocked;
      ++r.tally.blocked;
    }
    if (r.move != Move::kRoute) return;
    if (t_ >= r.ask_at && make_way(r, still)) {
      r.ask_at = t_ + kYieldAfter;
      return;
    }
    if (r.state == NavState::kBlocked && t_ - std::max(r.progress_at, r.retried_at) > params_.blocked_after)
      back_off(r);
  }

  // --- making way -----------------------------------------------------------

  // Robot r has made no progress for `still` [s]. The robot nearest in its
  // way ahead makes way: of two in each other's way (a door, a corridor),
  // after kHeadOnAfter, the higher id, or the other when it finds no spot
  // off the way; after kYieldAfter, an idle one as a courtesy (a short way
  // from where it stopped), or a driving one that r is not in the way of,
  // as it holds r up. False when nobody moves.
  bool make_way(Robot& r, double still) {
    way_ahead(r, kLookAhead, way_);
    Robot* in_way = nullptr;
    double nearest = 0.0;
    const Point2 at = position(r);
    for (const auto& o : robots_) {
      if (o->id == r.id || distance_to_way(position(*o), way_) >= 2 * radius_ + kInWay) continue;
      const double d = distance(position(*o), at);
      if (!in_way || d < nearest) in_way = o.get(), nearest = d;
    }
    if (!in_way || in_way->move != Move::kRoute) return false;  // nobody, or it is making way already
    Robot& o = *in_way;
    way_ahead(r, kClearAhead, keep_off_);
    if (driving(o)) {
      way_ahead(o, kLookAhead, way_);
      if (distance_to_way(at, way_) < 2 * radius_ + kInWay) {
        // Meeting: each keeps right; if neither can, and they stall, one
        // makes way.
        if (still < kHeadOnAfter) {
          const bool r_keeps_right = keep_right(r, o);
          return keep_right(o, r) || r_keeps_right;
        }
        way_ahead(o, kClearAhead, other_keep_off_);
        r.ask_at = t_ + kAskAgain;
        if (r.id > o.id)
          return aside(r, other_keep_off_, at, kAsideRange, o.id) ||
                 aside(o, keep_off_, position(o), kAsideRange, r.id);
        return aside(o, keep_off_, position(o), kAsideRange, r.id) || aside(r, other_keep_off_, at, kAsideRange, o.id);
      }
    }
    if (still < kYieldAfter) return false;
    r.ask_at = t_ + kAskAgain;
    if (!driving(o)) return aside(o, keep_off_, o.home, kCourtesyRange, r.id);
    return aside(o, keep_off_, position(o), kAsideRange, r.id);
  }

  // Robot r meets robot o head on: it heads first for a point on its right
  // where its way meets o's (halfway between them), as far aside as two
  // robots need to pass, or as far as there is room (o keeps right too).
  // False when there is none.
  bool keep_right(Robot& r, const Robot& o) {
    if (r.next < r.targets.size() && r.target_waypoint[r.next] == kPassing) return false;  // passing already
    const Point2 a = position(r);
    way_ahead(r, 0.5 * distance(a, position(o)), way_);
    const Point2 m = way_.back();
    const double d = distance(a, m);
    if (d < radius_) return false;
    Point2 p;
    bool room = false;
    for (double side = 2 * radius_ + kInWay; side > 0.5 * radius_ && !room; side -= map_.resolution()) {
      p = Point2{m.x + (m.y - a.y) / d * side, m.y - (m.x - a.x) / d * side};
      room = comfy_[map_.index(map_.world_to_cell(p))] && sight(comfy_, a, p, kLooseEnds) &&
             clear_of_robots(r, p, kSpotGap);
    }
    if (!room) return false;
    r.targets.insert(r.targets.begin() + static_cast<long>(r.next), p);
    r.target_waypoint.insert(r.target_waypoint.begin() + static_cast<long>(r.next), kPassing);
    r.target_reach.insert(r.target_reach.begin() + static_cast<long>(r.next), kPassTolerance);
    r.target_arc.insert(r.target_arc.begin() + static_cast<long>(r.next), r.target_arc[r.next]);
    issue(r);
    return true;
  }

  // Blocked: it backs off a little from what holds it, then plans a new way.
  void back_off(Robot& r) {
    r.retried_at = t_;
    Point2 spot;
    if (find_spot(r, {}, 0.0, position(r), kBackOffRange, kBackOffStep, spot))
      drive_aside(r, spot, -1);
    else
      resume(r);
  }

  // Robot y drives to the nearest spot off `keep_off`, within `range` of
  // `around`, to make way for robot `for_robot`.
  bool aside(Robot& y, const std::vector<Point2>& keep_off, Point2 around, double range, int for_robot) {
    Point2 spot;
    if (!find_spot(y, keep_off, kKeepOff, around, range, 0.0, spot) &&
        !find_spot(y, keep_off, kKeepOffTight, around, range, 0.0, spot))
      return false;
    drive_aside(y, spot, for_robot);
    return true;
  }

  void drive_aside(Robot& y, Point2 spot, int for_robot) {
    y.move = Move::kAside, y.make_way_for = for_robot, y.spot = spot;
    y.move_until = t_ + kAsideTimeout;
    y.nav_ended = y.nav_error = false;
    mrpt::nav::TWaypointSequence seq;
    seq.waypoints.emplace_back(spot.x, spot.y, kAsideTolerance, false);
    y.nav->navigateWaypoints(seq);
  }

  void hold(Robot& r) {
    r.move = Move::kHold;
    r.move_until = t_ + kHoldTimeout;
    r.nav->cancel();
    r.iface->stop(false);
  }

  void manoeuvre(Robot& r) {
    if (r.move == Move::kAside && (t_ > r.move_until || r.nav_ended || r.nav_error)) hold(r);
    if (r.move == Move::kHold &&
        (r.make_way_for < 0 || t_ > r.move_until || passed(*robots_[static_cast<std::size_t>(r.make_way_for)], r)))
      resume(r);
  }

  // Back on its way (a new one, from where it stands); an idle robot stays.
  void resume(Robot& r) {
    r.move = Move::kRoute, r.make_way_for = -1;
    if (!driving(r)) return;
    r.retried_at = t_;
    plan(r, r.reached);
    if (r.targets.empty()) {
      fail(r);
      return;
    }
    issue(r);
  }

  // Whether robot p no longer needs the way robot y made: it no longer
  // drives its way, or it is past y (clear of it and moving away).
  bool passed(const Robot& p, const Robot& y) {
    if (!driving(p) || p.move != Move::kRoute || p.next >= p.targets.size()) return true;
    const Point2 at = position(p), here = position(y);
    const double d = distance(at, here);
    if (d > kClearAhead) return true;
    way_ahead(p, kPassedAhead, way_);
    return d > 2 * radius_ + kInWay && distance(way_.back(), here) > d;
  }

  // The first `length` [m] of the robot's way from where it stands: straight
  // to its next target if it sees it, else back onto the way first.
  void way_ahead(const Robot& r, double length, std::vector<Point2>& out) const {
    out.clear();
    Point2 from = position(r);
    out.push_back(from);
    if (r.next < r.targets.size() && !sight(roomy_, from, r.targets[r.next], kLooseEnds)) {
      const Point2 a = r.next > 0 ? r.targets[r.next - 1] : r.way_from, b = r.targets[r.next];
      const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
      const double s = len2 > 0 ? std::clamp(((from.x - a.x) * dx + (from.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
      const Point2 onto{a.x + s * dx, a.y + s * dy};
      length -= distance(from, onto);
      out.push_back(onto), from = onto;
    }
    for (std::size_t k = r.next; k < r.targets.size() && length > 0; ++k) {
      const Point2 to = r.targets[k];
      const double d = distance(from, to);
      if (d >= length) {
        out.push_back(Point2{from.x + (to.x - from.x) * length / d, from.y + (to.y - from.y) * length / d});
        break;
      }
      out.push_back(to);
      length -= d, from = to;
    }
  }

  // [m] from p to the polyline `way` (infinite for none).
  static double distance_to_way(Point2 p, const std::vector<Point2>& way) {
    if (way.empty()) return std::numeric_limits<double>::infinity();
    double best = distance(p, way.front());
    for (std::size_t k = 1; k < way.size(); ++k) {
      const Point2 a = way[k - 1], b = way[k];
      const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
      const double s = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, distance(p, Point2{a.x + s * dx, a.y + s * dy}));
    }
    return best;
  }

  // Whether a disc of robot y at p keeps `gap` [m] beyond the two radii off every other robot.
  bool clear_of_robots(const Robot& y, Point2 p, double gap) const {
    for (const auto& o : robots_)
      if (o->id != y.id && distance(p, position(*o)) < 2 * radius_ + gap) return false;
    return true;
  }

  // Whether robot y drives straight from `from` to `to` touching no wall
  // and passing no other robot closer than kSpotGap beyond the two radii,
  // or than it is now (a spot past the robot it makes way for is no spot).
  bool straight_away(const Robot& y, Point2 from, Point2 to) {
    line_.assign({from, to});
    for (const auto& o : robots_) {
      if (o->id == y.id) continue;
      const Point2 q = position(*o);
      if (distance_to_way(q, line_) < std::min(2 * radius_ + kSpotGap, distance(q, from) - kContactSlack)) return false;
    }
    const double len = distance(from, to);
    const int n = static_cast<int>(std::ceil(len / map_.resolution()));
    for (int k = 1; k <= n; ++k)
      if (touches_wall(Point2{from.x + (to.x - from.x) * k / n, from.y + (to.y - from.y) * k / n})) return false;
    return true;
  }

  // The spot nearest robot y (breadth first over the cells it fits on,
  // not through other robots) within `range` of `around`, at least
  // `min_travel` from it, `gap` beyond the two radii off `keep_off` and
  // kSpotGap off the others.
  bool find_spot(const Robot& y, const std::vector<Point2>& keep_off, double gap, Point2 around, double range,
                 double min_travel, Point2& spot) {
    const Point2 from = position(y);
    const Cell start = lane_cell(roomy_, from);
    if (start.row < 0) return false;
    if (seen_.size() != map_.size() || ++generation_ == 0) seen_.assign(map_.size(), 0), generation_ = 1;
    queue_.clear();
    queue_.push_back(start);
    seen_[map_.index(start)] = generation_;
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const Cell c = queue_[head];
      const Point2 p = map_.cell_center(c);
      if (distance(p, from) >= min_travel && distance_to_way(p, keep_off) >= 2 * radius_ + gap &&
          clear_of_robots(y, p, kSpotGap) && straight_away(y, from, p)) {
        spot = p;
        return true;
      }
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const Cell n{c.row + dr, c.col + dc};
          if ((dr == 0 && dc == 0) || !map_.contains(n)) continue;
          const std::size_t i = map_.index(n);
          if (seen_[i] == generation_ || !roomy_[i]) continue;
          seen_[i] = generation_;
          const Point2 q = map_.cell_center(n);
          if (distance(q, around) <= range && clear_of_robots(y, q, 0.0)) queue_.push_back(n);
        }
    }
    return false;
  }

  // --- the laser ----------------------------------------------------------

  void laser(Robot& r, mrpt::maps::CSimplePointsMap& out) {
    const TPose2D p = r.veh->getCurrentGTPose();
    const double range = params_.laser_range, rr = radius_ * radius_;
    near_.clear();
    for (const auto& o : robots_) {
      if (o->id == r.id) continue;
      const TPose2D q = o->veh->getCurrentGTPose();
      const double dx = q.x - p.x, dy = q.y - p.y, d2 = dx * dx + dy * dy;
      if (d2 < (range + radius_) * (range + radius_)) near_.push_back({dx, dy, d2 - rr});
    }
    const double fov = params_.laser_fov * kPi / 180.0;
    const bool full = params_.laser_fov >= 359.999;
    const int n = params_.laser_rays;
    const double step = full ? fov / n : fov / (n - 1);
    // Returns closer than the footprint's edge (robots touching) are put at
    // it: the navigator would otherwise see every way blocked for good.
    const double closest = radius_ + 0.12;
    out.clear();
    r.scan_pose = p, r.scan_t = t_;
    r.ranges.assign(static_cast<std::size_t>(n), std::numeric_limits<float>::infinity());
    for (int k = 0; k < n; ++k) {
      const double local = -0.5 * fov + k * step, a = p.phi + local;
      float hit = 0.0f;
      bool valid = false;
      laser_map_.simulateScanRay(p.x, p.y, a, hit, valid, static_cast<float>(range), 0.4f);
      double d = valid ? static_cast<double>(hit) : range;
      const double ux = std::cos(a), uy = std::sin(a);
      for (const auto& o : near_) {
        const double b = o.dx * ux + o.dy * uy;
        if (b <= 0) continue;
        const double disc = b * b - o.c;
        if (disc < 0) continue;
        const double h = b - std::sqrt(disc);
        if (h >= 0 && h < d) d = h, valid = true;
      }
      if (!valid) continue;
      r.ranges[static_cast<std::size_t>(k)] = static_cast<float>(d);  // as far as it really is
      d = std::max(d, closest);
      out.insertPoint(static_cast<float>(d * std::cos(local)), static_cast<float>(d * std::sin(local)), 0.0f);
    }
  }

  // --- stepping -----------------------------------------------------------

  // Drives the robot itself instead of a navigation step where the
  // navigator does badly: towards a waypoint (or the spot it makes way at)
  // close by in the open, straight (its trajectories, metres long, make
  // a robot circle a point a few decimetres off); and turning on the spot
  // while its way lies behind it. Returns whether it did.
  bool steer(Robot& r) {
    const Point2 at = position(r);
    Point2 aim = r.spot;
    double reach = kAsideTolerance;  // closer than this to `aim`, it is there
    int waypoint = -1;               // the target `aim` is, if a waypoint of the way
    if (r.move == Move::kRoute && r.next < r.targets.size()) {
      // Its way's point kTurnAim ahead, or the waypoint before it.
      Point2 from = at;
      double left = kTurnAim;
      for (std::size_t k = r.next; k < r.targets.size(); ++k) {
        const Point2 to = r.targets[k];
        const double d = distance(from, to);
        const int w = r.target_waypoint[k];
        if (d >= left) {
          aim = Point2{from.x + (to.x - from.x) * left / d, from.y + (to.y - from.y) * left / d}, reach = 0.0;
          break;
        }
        aim = to, reach = r.target_reach[k];
        if (w >= 0) {
          waypoint = static_cast<int>(k);
          break;
        }
        left -= d, from = to;
      }
    } else if (r.move != Move::kAside) {
      return r.turning = false;
    }
    const bool exact = r.move == Move::kAside || waypoint >= 0;
    const double d = distance(aim, at);
    if (exact && d <= reach) {  // there: the navigator goes on from the next target
      r.turning = false;
      if (r.move == Move::kAside) {
        hold(r);
      } else {
        target_reached(r, waypoint - static_cast<int>(r.issued_from));
        issue(r);
      }
      return true;
    }
    const double heading = r.veh->getCurrentGTPose().phi;
    const double off = mrpt::math::angDistance(heading, std::atan2(aim.y - at.y, aim.x - at.x));
    const double w_max = params_.max_turn_rate * kPi / 180.0;
    mrpt::kinematics::CVehicleVelCmd_DiffDriven c;
    c.ang_vel = std::copysign(std::min(w_max, std::abs(off) / params_.nav_period), off);
    if (exact && d < kDirectRange && straight_clear(r, at, aim, reach)) {
      r.turning = false;
      if (std::abs(off) < kDirectAligned)
        c.lin_vel = std::clamp((d - reach) / params_.nav_period, kCreep, v_),
        c.ang_vel = std::clamp(2.0 * off, -w_max, w_max);
      r.iface->changeSpeeds(c);
      return true;
    }
    r.turning = std::abs(off) > (r.turning ? kTurnDone : kTurnStart);
    if (r.turning) r.iface->changeSpeeds(c);
    return r.turning;
  }

  // Whether the robot at `from` goes straight to within `reach` of `to`
  // (a little further) touching no wall, keeping kSpotGap off the other robots.
  bool straight_clear(const Robot& r, Point2 from, Point2 to, double reach) {
    const double d = std::max(distance(from, to), 1e-9), len = std::max(0.0, d - 0.8 * reach);
    const int n = static_cast<int>(std::ceil(len / map_.resolution()));
    const double ux = (to.x - from.x) / d, uy = (to.y - from.y) / d;
    line_.assign({from, Point2{from.x + ux * len, from.y + uy * len}});
    for (int k = 1; k <= n; ++k)
      if (touches_wall(Point2{from.x + ux * len * k / n, from.y + uy * len * k / n})) return false;
    for (const auto& o : robots_)
      if (o->id != r.id && distance_to_way(position(*o), line_) < 2 * radius_ + kSpotGap) return false;
    return true;
  }

  // Whether a disc of `rad` [m] at p overlaps a cell no robot may enter
  // (occupied, unknown, off the map), square for square: the clearance
  // map's bound is up to a cell diagonal short, which near a wall is the
  // difference between a waypoint in reach and one out of it.
  bool hits_wall(Point2 p, double rad) const {
    if (clearance_.free_distance(p) >= rad) return false;
    const double res = map_.resolution(), half = 0.5 * res;
    const Cell c = map_.world_to_cell(p);
    const int k = static_cast<int>(std::ceil(rad / res)) + 1;
    for (int dr = -k; dr <= k; ++dr)
      for (int dc = -k; dc <= k; ++dc) {
        const Cell n{c.row + dr, c.col + dc};
        if (map_.contains(n) && map_.is_free(n)) continue;
        const Point2 q = map_.cell_center(n);
        const double dx = std::max(0.0, std::abs(p.x - q.x) - half), dy = std::max(0.0, std::abs(p.y - q.y) - half);
        if (dx * dx + dy * dy < rad * rad) return true;
      }
    return false;
  }

  bool touches_wall(Point2 p) const { return hits_wall(p, radius_ - kContactSlack); }

  // Walls and robots are solid: a move from `a` into contact with either
  // ends where the contact begins (a robot in contact already may not get
  // any deeper), its turn kept (a disc turns in place: a robot against
  // another can still turn away from it). Returns whether a robot stopped it.
  bool contact(const Robot& r, const TPose2D& a, TPose2D& b) const {
    const Point2 from{a.x, a.y};
    const bool wall_before = touches_wall(from);
    bool robot_hit = false;
    auto clear = [&](double s, bool& by_robot) {
      const Point2 p{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)};
      by_robot = false;
      for (const auto& o : robots_) {
        if (o->id == r.id) continue;
        const Point2 q = position(*o);
        const double d = distance(p, q);
        if (d < 2 * radius_ && d < distance(from, q)) by_robot = true;
      }
      return !by_robot && (wall_before || !touches_wall(p));
    };
    if (clear(1.0, robot_hit)) return false;
    double lo = 0.0, hi = 1.0;
    bool ignored = false;
    for (int k = 0; k < 10; ++k) {
      const double mid = 0.5 * (lo + hi);
      (clear(mid, ignored) ? lo : hi) = mid;
    }
    b.x = a.x + lo * (b.x - a.x), b.y = a.y + lo * (b.y - a.y);
    return robot_hit;
  }

  void step(double t) {
    const double dt = t - t_;
    t_ = t;
    mrpt::Clock::setSimulatedTime(epoch_ +
                                  std::chrono::duration_cast<mrpt::Clock::duration>(std::chrono::duration<double>(t)));
    if (dt <= 0) return;
    const auto n0 = Steady::now();
    for (auto& rp : robots_) {
      Robot& r = *rp;
      if (t + 1e-9 < r.next_nav) continue;
      while (r.next_nav <= t + 1e-9) r.next_nav += params_.nav_period;
      if (driving(r) || r.move != Move::kRoute) {
        if (!steer(r)) r.nav->navigationStep();
        follow(r);
      }
    }
    const auto v0 = Steady::now();
    for (auto& rp : robots_) {
      Robot& r = *rp;
      if (r.watchdog > 0 && t - r.last_cmd > r.watchdog + 1e-9) {
        r.iface->stop(true);
        r.watchdog = -1;
      }
      const TPose2D a = r.veh->getCurrentGTPose();
      r.veh->step(dt);
      const TPose2D moved = r.veh->getCurrentGTPose();
      TPose2D b = moved;
      const bool pressed = contact(r, a, b);
      if (b.x != moved.x || b.y != moved.y) {
        TPose2D odo = r.veh->getCurrentOdometricPose();
        odo.x += b.x - moved.x, odo.y += b.y - moved.y;
        r.veh->setCurrentGTPose(b);
        r.veh->setCurrentOdometricPose(odo);
      }
      r.tally.driven_m += std::hypot(b.x - a.x, b.y - a.y);
      const bool touching = pressed || !clear_of_robots(r, Point2{b.x, b.y}, 0.01);
      if (touching && !r.touching) ++r.tally.contacts;
      r.touching = touching;
    }
    const auto e = Steady::now();
    nav_ms_ += std::chrono::duration<double, std::milli>(v0 - n0).count();
    vehicle_ms_ += std::chrono::duration<double, std::milli>(e - v0).count();
  }

  agent::RobotPose pose(const Robot& r, int64_t tick) const {
    agent::RobotPose p;
    const TPose2D g = r.veh->getCurrentGTPose();
    const mrpt::math::TTwist2D v = r.veh->getCurrentGTVel();
    p.agent = static_cast<int16_t>(r.id), p.tick = tick, p.stamp = t_;
    p.at = Point2{g.x, g.y}, p.heading = g.phi;
    p.v = std::hypot(v.vx, v.vy), p.w = v.omega;
    p.sigma = 0.0;
    return p;
  }

  agent::NavStatus status(const Robot& r, int64_t tick) const {
    agent::NavStatus s;
    s.agent = static_cast<int16_t>(r.id), s.tick = tick, s.stamp = t_;
    s.command = r.has_cmd ? r.cmd.id : 0;
    s.state = r.state;
    s.reached = static_cast<uint16_t>(r.reached);
    std::copy(r.reached_at, r.reached_at + r.reached, s.reached_at);
    s.contacts = static_cast<int32_t>(std::min<int64_t>(r.tally.contacts, 2147483647));
    if (driving(r) && r.next < r.targets.size()) {
      s.has_eta = true;
      s.eta = t_ + way_left(r) / v_;  // at top speed
    }
    return s;
  }

  WorldParams params_;
  const OccupancyGrid& map_;
  double radius_, v_;
  ClearanceMap clearance_;
  Mask roomy_, comfy_;
  double comfy_keep_;                             // [m] the clearance of a comfy cell
  std::vector<int32_t> roomy_part_, comfy_part_;  // their connected parts (label())
  std::unique_ptr<GridAStar> planner_, comfy_planner_;
  std::vector<Cell> cells_;
  std::vector<std::size_t> blocked_;  // roomy cells taken by other robots while planning
  // plan()'s first way, while it looks for one around robots standing on it.
  std::vector<Point2> spare_targets_;
  std::vector<int> spare_waypoint_;
  std::vector<double> spare_reach_, spare_arc_;
  mrpt::maps::COccupancyGridMap2D laser_map_;
  std::vector<std::unique_ptr<Robot>> robots_;
  mrpt::Clock::time_point epoch_;
  double t_ = 0.0;
  mrpt::maps::CSimplePointsMap view_points_;  // scratch of scan()
  double nav_ms_ = 0.0, vehicle_ms_ = 0.0;

 private:
  struct Near {
    double dx, dy, c;
  };
  std::vector<Near> near_;
  std::vector<Point2> way_, keep_off_, other_keep_off_, line_;
  // find_spot's breadth-first search: cells seen in search `generation_`.
  std::vector<uint32_t> seen_;
  uint32_t generation_ = 0;
  std::vector<Cell> queue_;
};

MrptWorld::MrptWorld(const OccupancyGrid& map, const std::vector<Point2>& starts, double team_speed, double team_radius,
                     const WorldParams& params)
    : impl_(std::make_unique<Impl>(map, starts, team_speed, team_radius, params)) {}

MrptWorld::~MrptWorld() = default;

void MrptWorld::step(int64_t tick, double t, const std::vector<agent::NavCommand>& commands,
                     std::vector<agent::RobotPose>& poses, std::vector<agent::NavStatus>& statuses) {
  for (const agent::NavCommand& c : commands) impl_->take(c);
  impl_->step(t);
  poses.clear(), statuses.clear();
  for (const auto& r : impl_->robots_) {
    poses.push_back(impl_->pose(*r, tick));
    statuses.push_back(impl_->status(*r, tick));
  }
}

int MrptWorld::robots() const { return static_cast<int>(impl_->robots_.size()); }
const RobotTally& MrptWorld::tally(int robot) const {
  return impl_->robots_.at(static_cast<std::size_t>(robot))->tally;
}
void MrptWorld::scan(int robot, agent::RobotScan& out) {
  auto& r = *impl_->robots_.at(static_cast<std::size_t>(robot));
  const WorldParams& p = impl_->params_;
  // A robot that is not navigating takes no scans: one now (it changes
  // nothing the robots do).
  if (r.scan_t < 0 || impl_->t_ - r.scan_t > p.nav_period + 1e-9) impl_->laser(r, impl_->view_points_);
  out.agent = static_cast<int16_t>(robot);
  const double fov = p.laser_fov * kPi / 180.0;
  const bool full = p.laser_fov >= 359.999;
  out.stamp = r.scan_t;
  out.at = Point2{r.scan_pose.x, r.scan_pose.y};
  out.heading = r.scan_pose.phi;
  out.angle_min = static_cast<float>(-0.5 * fov);
  out.angle_increment = static_cast<float>(full ? fov / p.laser_rays : fov / (p.laser_rays - 1));
  out.range_max = static_cast<float>(p.laser_range);
  out.rays = static_cast<uint16_t>(std::min<std::size_t>(r.ranges.size(), agent::kMaxScanRays));
  std::copy(r.ranges.begin(), r.ranges.begin() + out.rays, out.ranges);
}
double MrptWorld::radius() const { return impl_->radius_; }
double MrptWorld::max_speed() const { return impl_->v_; }
double MrptWorld::nav_ms() const { return impl_->nav_ms_; }
double MrptWorld::vehicle_ms() const { return impl_->vehicle_ms_; }

}  // namespace world
}  // namespace gather
