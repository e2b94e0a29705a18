// The agent side of the lockstep (LockstepAgent; the protocol is in
// gather_agent/runner/lockstep.hpp): take the plan, then step the role tick
// by tick on the OC's clock, or on the wall clock.
#include "gather_agent/runner/lockstep.hpp"

#include <malloc.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "gather_agent/roles/worker_role.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/mission_csv.hpp"
#include "lockstep_shared.hpp"

namespace gather {
namespace agent {

using namespace lockstep;  // lockstep_shared.hpp: the held messages, the clocks
namespace {

std::string seconds_text(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", s);
  return b;
}

}  // namespace

// --- agent -----------------------------------------------------------------

LockstepAgent::LockstepAgent(LoadedPlan& plan, int id, LcmFleet& fleet, LcmRobotLink* robot,
                             const RobotBaseParams& robot_params)
    : plan_(plan), id_(id), fleet_(fleet), digest_(plan_digest(plan)), robot_(robot), robot_params_(robot_params) {
  check_params(robot_params);
  robot_poses_.reserve(64);
  robot_statuses_.reserve(64);
  if (id < 0 || id >= static_cast<int>(plan.plan.file.agents.size()))
    throw Error(plan.dir, "agent --id " + std::to_string(id) + " is not in the plan's team of " +
                              std::to_string(plan.plan.file.agents.size()));
  malloc_trim(0);  // the map at full resolution was read and coarsened: give it back
  world_ = std::make_unique<mission::World>(plan.scenario);
  held_.reserve(kHeld);
  current_.reserve(kHeld);
  inbox_.reserve(1024);
  reply_.keys.reserve(4096);
  reply_.measured_goals.reserve(kReplyMaxPoints);
  unreported_.reserve(kReplyMaxPoints);
  reply_.path.reserve(kReplyMaxPoints);
}

LockstepAgent::~LockstepAgent() = default;

void LockstepAgent::set_journal(const std::string& dir, bool rejoin) {
  journal_dir_ = dir;
  rejoin_ = rejoin && !dir.empty();
}

bool LockstepAgent::take_plan(std::string* why) {
  const PlanAnnounce& p = fleet_.plans().back();
  char hex[2][17];
  std::snprintf(hex[0], sizeof hex[0], "%016llx", static_cast<unsigned long long>(digest_));
  std::snprintf(hex[1], sizeof hex[1], "%016llx", static_cast<unsigned long long>(p.digest));
  if (p.digest != digest_) {
    *why = plan_.dir + ": this agent's plan (plan.yaml, labels, scenario, map) has digest " + hex[0] + ", the OC's " +
           hex[1] + ": they are not the same plan";
    return false;
  }
  if (p.agents != static_cast<int>(plan_.plan.file.agents.size())) {
    *why = plan_.dir + ": the OC runs a team of " + std::to_string(p.agents) + " agents";
    return false;
  }
  if (p.robots != (robot_ != nullptr)) {
    *why = p.robots ? "the OC runs the team on robots: start this agent with --motion lcm"
                    : "the OC runs the team on ideal bases: start this agent with --motion sim";
    return false;
  }
  try {
    team_ = std::make_unique<TeamSetup>(*world_, plan_.plan, p.params);
    gate_ = std::make_unique<RangeGate>(*team_, p.loss, p.loss_seed);
    unit_ = make_agent(*team_, AgentId(id_), nullptr, robot_, robot_params_);
    if (!journal_dir_.empty()) {
      journal_ = std::make_unique<JournalKeeper>(journal_path(journal_dir_, id_), id_, journal_run_id(team_->params));
      rejoin_state_ = journal_->open(rejoin_);
      if (rejoin_ && !rejoin_state_.matched)
        throw Error(journal_path(journal_dir_, id_), "--rejoin: no journal of this agent and mission to replay");
      // Where it was; what it held and how far it got come back at its first tick.
      if (rejoin_)
        unit_ = make_agent(*team_, AgentId(id_), rejoin_state_.have_pose ? &rejoin_state_.pose : nullptr, robot_,
                           robot_params_);
      journal_->bind(*unit_.role);
    }
  } catch (const std::exception& e) {  // its plan cannot be run as the OC asks: refuse it
    *why = e.what();
    team_.reset();
    return false;
  }
  base_ = robot_ ? static_cast<RobotBase*>(unit_.motion.get()) : nullptr;
  if (robot_ && p.clock == ClockMode::kWall && p.rate != 1.0)
    std::fprintf(stderr,
                 "gather_agent %d: the mission runs %g x real time: a real robot needs 1 (only a simulated one that "
                 "runs %g x as fast keeps up)\n",
                 id_, p.rate, p.rate);
  outbox_ = std::make_unique<Outbox>(kOutbox);
  tick_s_ = p.tick;
  clock_ = p.clock;
  rate_ = p.rate;
  fleet_.set_team(p.agents, team_->collector_flags(), team_->links);
  // A repair (a repaired plan merges segments: docs/faults.md) reads the
  // label image again from the plan directory.
  team_->reload_labels = [dir = plan_.dir, frame = plan_.plan.labels.frame()]() {
    LabelImage labels = mission::load_mission_plan(dir).labels;
    if (!labels.frame().same_size(frame))
      throw RuntimeError(dir, "labels.png is now " + labels.frame().size_text() + ", it was " + frame.size_text());
    labels.reframe(frame);
    return labels;
  };
  plan_.plan.labels.release();
  malloc_trim(0);  // give back what loading the map and the plan used and freed
  return true;
}

bool LockstepAgent::inbox_complete(const Tick& tick) const {
  // With its own links' keys it takes only what was sent to it.
  const bool own = !fleet_.sees_all() && static_cast<std::size_t>(id_) < tick.expect.size();
  return count_tick(held_, tick.tick) >= static_cast<std::size_t>(own ? tick.expect[id_] : tick.sent_before);
}

void LockstepAgent::absorb_robot() {
  if (!robot_) return;
  robot_->handle(0);
  for (const RobotPose& p : robot_->poses()) robot_poses_.push_back(p);
  for (const NavStatus& s : robot_->statuses()) robot_statuses_.push_back(s);
  robot_heard_ = robot_heard_ || !robot_->poses().empty();
  robot_->poses().clear(), robot_->statuses().clear();
  // On the lockstep clock, reports of ticks already stepped (or sent before
  // the mission) are of no more use; on the wall clock every report is taken
  // at the next step (feed_robot).
  if (clock_ != ClockMode::kLockstep) return;
  const auto old = [&](int64_t t) { return t < next_tick_; };
  robot_poses_.erase(
      std::remove_if(robot_poses_.begin(), robot_poses_.end(), [&](const RobotPose& p) { return old(p.tick); }),
      robot_poses_.end());
  robot_statuses_.erase(
      std::remove_if(robot_statuses_.begin(), robot_statuses_.end(), [&](const NavStatus& s) { return old(s.tick); }),
      robot_statuses_.end());
}

bool LockstepAgent::robot_reported(int64_t tick) const {
  if (!robot_) return true;
  bool pose = false, status = false;
  for (const RobotPose& p : robot_poses_) pose = pose || p.tick == tick;
  for (const NavStatus& s : robot_statuses_) status = status || s.tick == tick;
  return pose && status;
}

// Hands the robot's reports to its base: those of lockstep tick `tick`, or
// (tick < 0, wall clock) all that came, at mission time `now`.
void LockstepAgent::feed_robot(int64_t tick, double now) {
  if (!base_) return;
  for (const RobotPose& p : robot_poses_)
    if (tick < 0 || p.tick == tick) base_->on_pose(p, now);
  for (const NavStatus& s : robot_statuses_)
    if (tick < 0 || s.tick == tick) base_->on_status(s, now);
  if (tick < 0) robot_poses_.clear(), robot_statuses_.clear();
  base_->set_tick(tick);
}

// One line on stderr when its robot becomes faulty (or well again).
void LockstepAgent::report_fault(double now) {
  if (!base_ || base_->fault() == fault_said_) return;
  fault_said_ = base_->fault();
  if (fault_said_ != BaseFault::kNone)
    std::fprintf(stderr, "gather_agent %d: %s (%s)\n", id_, base_->fault_text().c_str(),
                 robot_pose_channel(id_).c_str());
  else
    std::fprintf(stderr, "gather_agent %d: robot reports again at t = %.1f s\n", id_, now);
}

void LockstepAgent::step(const Tick& tick) {
  const auto s0 = Clock::now();
  Role& role = *unit_.role;
  feed_robot(tick.tick, tick.t);
  const int64_t commands_before = robot_ ? robot_->sent() : 0;
  unit_.motion->update(tick.t);
  if (rejoin_) {  // a new process heard nothing of the tick before it joined
    held_.erase(std::remove_if(held_.begin(), held_.end(), [&](const Message& m) { return m.h.tick < tick.tick; }),
                held_.end());
    current_.clear();
    inbox_.clear();
    rejoin_ = false;
    const JournalState& s = rejoin_state_;
    role.restore(s.custody.data(), s.custody.size(), s.progress, tick.t);
  } else {
    take_tick(held_, current_, tick.tick, late_);
    gather_inbox(current_, role.id(), unit_.motion->pose(), *gate_, link_, inbox_);
  }
  Outbox& out = *outbox_;
  out.clear();
  role.control(tick.t, inbox_.data(), inbox_.size(), out);
  if (journal_) journal_->after_step(*unit_.motion, tick.t);  // durable before its messages go out
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].h.seq = seq_++;
    out[k].h.tick = tick.tick;
    fleet_.publish(out[k]);
  }
  link_.sent += static_cast<int64_t>(out.size());
  link_.bad = fleet_.dropped();
  report_fault(tick.t);
  step_us_ += std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - s0).count();
  reply_.step_us = step_us_;
  reply_.tick = tick.tick;
  reply_.agent = static_cast<int16_t>(id_);
  reply_.status = ReplyStatus::kStepped;
  reply_.sent = static_cast<int32_t>(out.size());
  reply_.dests.clear();
  for (std::size_t k = 0; k < out.size(); ++k) reply_.dests.push_back(out[k].h.dest);
  reply_.commands = robot_ ? static_cast<int32_t>(robot_->sent() - commands_before) : 0;
  reply_.pose = unit_.motion->pose();
  reply_.heading = unit_.motion->heading();
  reply_.nav_state = unit_.motion->state();
  reply_.robot_fault = unit_.motion->fault();
  if (base_) {
    const RobotLinkCounters& c = base_->counters();
    reply_.contacts = base_->contacts();
    reply_.robot_dropped = static_cast<int32_t>(c.bad_pose + c.lost_pose + c.stale_status + c.bad_status +
                                                robot_->refused().total() + robot_->rejected().total());
    reply_.robot_faults = static_cast<int32_t>(c.faults);
  }
  reply_.role = role.kind();
  reply_.phase = role.kind() == RoleKind::kWorker ? static_cast<int>(static_cast<const WorkerRole&>(role).phase()) : 0;
  reply_.report = role.report();
  const Custody* c = role.custody();
  reply_.carried = c ? static_cast<int32_t>(c->data()) : 0;
  reply_.notices = c ? static_cast<int32_t>(c->notices()) : 0;
  reply_.link = link_;
  reply_.auth = fleet_.rejected();
  reply_.late = late_;
  reply_.incomplete = incomplete_;
  reply_.keys.clear();
  if (tick.report && c)
    for (std::size_t i = 0; i < c->size(); ++i)
      if (c->item(i).kind == ItemKind::kMeasured) reply_.keys.push_back(c->item(i).key);
  // For the OC's views and its conservation check: what it measured (more
  // than a reply holds waits for the next one), and its path when that changed.
  if (const std::vector<GoalId>* m = role.measured_in_step())
    for (GoalId g : *m) unreported_.push_back(g.value());
  reply_.measured_goals.clear();
  const std::size_t now = std::min(unreported_.size(), kReplyMaxPoints);
  reply_.measured_goals.assign(unreported_.begin(), unreported_.begin() + static_cast<std::ptrdiff_t>(now));
  unreported_.erase(unreported_.begin(), unreported_.begin() + static_cast<std::ptrdiff_t>(now));
  reply_.path.clear();
  if (unit_.motion->path_revision() != reply_.path_revision) {
    reply_.path_revision = unit_.motion->path_revision();
    reply_.path.resize(kReplyMaxPoints);
    reply_.path.resize(unit_.motion->path(reply_.path.data(), kReplyMaxPoints));
  }
  fleet_.publish(reply_);
}

// Wall-clock mode: the role steps every tick_s_ / rate_ seconds of wall time
// with whatever arrived since the step before (through the gate, in
// (sender, seq) order); nothing waits for anybody, so a run is not
// reproducible, as on real robots.
void LockstepAgent::step_wall(double t) {
  Role& role = *unit_.role;
  feed_robot(-1, t);
  unit_.motion->update(t);
  if (rejoin_) {  // a restart: what it held and how far it got, now
    rejoin_ = false;
    role.restore(rejoin_state_.custody.data(), rejoin_state_.custody.size(), rejoin_state_.progress, t);
  }
  current_.swap(held_);
  held_.clear();
  gather_inbox(current_, role.id(), unit_.motion->pose(), *gate_, link_, inbox_);
  Outbox& out = *outbox_;
  out.clear();
  role.control(t, inbox_.data(), inbox_.size(), out);
  if (journal_) journal_->after_step(*unit_.motion, t);  // durable before its messages go out
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].h.seq = seq_++;
    out[k].h.tick = -1;
    fleet_.publish(out[k]);
  }
  link_.sent += static_cast<int64_t>(out.size());
  report_fault(t);
}

LockstepAgent::End LockstepAgent::run(ShutdownSignal& signal, double silence_s, std::string* why) {
  auto heard = Clock::now();
  bool have_tick = false;
  Tick pending;
  auto tick_since = Clock::now();
  for (;;) {
    if (signal.wait_until(Clock::now())) return End::kStopped;
    fleet_.keep_time();
    fleet_.handle(have_tick ? 20 : wall_start_us_ > 0 ? wall_wait_ms_ : 100, robot_ ? robot_->fileno() : -1);
    absorb(fleet_, held_, link_);
    absorb_robot();
    if (fleet_.clock().synced() && !offset_said_) {
      offset_said_ = true;
      std::printf("gather_agent %d: clock offset to the OC %+.3f s (round trip %.1f ms)\n", id_,
                  static_cast<double>(fleet_.clock().offset_us()) * 1e-6,
                  static_cast<double>(fleet_.clock().round_trip_us()) * 1e-3);
      std::fflush(stdout);
    }
    if (!fleet_.plans().empty()) {
      heard = Clock::now();
      if (!team_ && !take_plan(why)) {
        Reply r;
        r.tick = -1, r.agent = static_cast<int16_t>(id_), r.status = ReplyStatus::kRefused;
        fleet_.publish(r);
        return End::kRefused;
      }
      if (next_tick_ == 0 && robot_ && !robot_heard_) {  // not READY before its robot has reported
        if (!waiting_said_) {
          std::printf("gather_agent %d: waiting for its robot (%s)\n", id_, robot_pose_channel(id_).c_str());
          std::fflush(stdout);
          waiting_said_ = true;
        }
      } else if (next_tick_ == 0) {  // (again) READY: the OC may not have heard the last one
        Reply r;
        r.tick = -1, r.agent = static_cast<int16_t>(id_), r.status = ReplyStatus::kReady;
        r.pid = static_cast<int32_t>(getpid());
        r.role = unit_.role->kind();
        r.pose = unit_.motion->pose();
        fleet_.publish(r);
      }
      fleet_.plans().clear();
    }
    for (const Tick& t : fleet_.ticks()) {
      heard = Clock::now();
      if (!team_) continue;
      if (t.done) return End::kDone;
      if (clock_ == ClockMode::kWall) {
        if (wall_start_us_ == 0 && t.start_us > 0) wall_start_us_ = t.start_us, next_tick_ = 1;
        continue;
      }
      if (t.tick < next_tick_) continue;
      if (!have_tick || t.tick < pending.tick) pending = t, have_tick = true, tick_since = Clock::now();
    }
    fleet_.ticks().clear();
    if (clock_ == ClockMode::kWall && wall_start_us_ > 0) {
      // Mission time from the wall clock; a step each tick_s_ / rate_ of wall time.
      // The fleet's time: this host's clock corrected by its offset to the OC.
      const double t = static_cast<double>(fleet_.clock().now_us() - wall_start_us_) * 1e-6 * rate_;
      if (t >= wall_next_) {
        step_wall(std::max(0.0, t));
        wall_next_ = std::max(wall_next_ + tick_s_, t);
      }
      wall_wait_ms_ = std::clamp(static_cast<int>((wall_next_ - t) / rate_ * 1000.0), 0, 20);
      if (seconds_since(heard) > silence_s) {
        *why = "nothing heard from the OC for " + seconds_text(silence_s) + " s";
        return End::kSilent;
      }
      continue;
    }
    // A tick runs once every message of the one before is in; if some never
    // come (lost on the host), it runs without them after a while.
    while (have_tick &&
           (rejoin_ || (inbox_complete(pending) && robot_reported(pending.tick)) || seconds_since(tick_since) > 5.0)) {
      if (!rejoin_ && !(inbox_complete(pending) && robot_reported(pending.tick))) ++incomplete_;
      step(pending);
      next_tick_ = pending.tick + 1;
      have_tick = false;
    }
    if (seconds_since(heard) > silence_s) {
      *why = "nothing heard from the OC for " + seconds_text(silence_s) + " s";
      return End::kSilent;
    }
  }
}

}  // namespace agent
}  // namespace gather
