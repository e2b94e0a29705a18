#pragma once
// Figures of the mission simulator, after the seed's Fig. 3 (estimated E
// curves and real R min-max bands over seeds) and Fig. 4 (a worker's and its
// collector's trajectories; a snapshot of the mission).
#include <string>
#include <vector>

#include "gather_core/mission/simulator.hpp"
#include "gather_core/partition/partition.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace figures {

// One configuration of the sweep: the planner's estimates and the simulated
// values of each seed.
struct ConfigRuns {
  partition::Method method = partition::Method::kBap;
  int collectors = 0;
  double est_refresh_s = 0.0, est_interval_s = 0.0, est_goals = 0.0, est_utility = 0.0;
  // per seed: mean latency [s], mean interval [s], goals delivered per cycle
  std::vector<double> refresh_s, interval_s, goals;
};

// Utility of each seed's simulated values, min-max normalised over the
// configurations for that seed (as the planner does for the estimates):
// result[config][seed].
// `m` picks the refresh metric (the scenario's planner.refresh).
std::vector<std::vector<double>> simulated_utilities(const std::vector<ConfigRuns>& runs, double alpha, double beta,
                                                     RefreshMetric m);

// DIR/fig3_refresh.png (latency), DIR/fig3_interval.png, DIR/fig3_goals.png,
// DIR/fig3_utility.png (U on the refresh metric m): per method
// the estimated curve (E, dashed) and the simulated min-max band over seeds
// with its mean (R) against N_c. Throws gather::Error naming a file that
// cannot be written.
void write_fig3(const std::string& dir, const std::vector<ConfigRuns>& runs, const std::vector<std::string>& methods,
                double alpha, double beta, RefreshMetric m);

// Fig. 4a: the trajectory of worker `agent` and of its collector during
// [t0, t1] [s] on the map (worker blue, collector red; meetings marked).
void write_fig4_sync(const std::string& path, const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                     const mission::MissionResult& result, AgentId agent, double t0, double t1);

// Fig. 4b: the mission at time t [s]: OC, segments, collector routes,
// collectors (squares) and workers (discs, coloured by their collector; black
// for OC workers), goals of the current request by state.
void write_fig4_snapshot(const std::string& path, const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                         const mission::MissionResult& result, double t);

// An animation of the mission (the seed's demo video): `frames` Fig. 4b
// frames evenly from t = 0 to the end of the run (the last delivery), at
// `fps` frames per second; .mp4 (MPEG-4 Part 2) or .avi (Motion JPEG) by
// OpenCV's FFmpeg backend. Throws gather::Error naming the file for another
// extension or when it cannot be written.
// Loads the video's encoder (the module libgather_video.so) now, so that a
// run that is to end in a video fails before it starts when it cannot be
// written: throws gather::Error("<path>: ...") naming where it looked.
void check_video_encoder(const std::string& path);

void write_mission_video(const std::string& path, const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                         const mission::MissionResult& result, double fps = 10.0, int frames = 300);

}  // namespace figures
}  // namespace gather
