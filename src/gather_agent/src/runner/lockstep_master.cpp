// The OC side of the lockstep (LockstepMaster; the protocol is in
// gather_agent/runner/lockstep.hpp): announce the plan, drive the ticks and
// collect the replies, restart agents, and report what the fleet did.
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

// --- master ----------------------------------------------------------------

namespace {

Tick clock_tick(int64_t k, double t, int64_t start_us) {
  Tick tick;
  tick.tick = k, tick.t = t, tick.start_us = start_us;
  return tick;
}

}  // namespace

LockstepMaster::LockstepMaster(TeamSetup& team, LcmFleet& fleet, uint64_t digest, const MasterOptions& options)
    : team_(team),
      fleet_(fleet),
      digest_(digest),
      options_(options),
      gate_(team, options.loss, options.loss_seed),
      oc_(make_oc(team)),
      outbox_(kOutbox) {
  if (!(options_.tick > 0.0) || options_.tick > 0.1 + 1e-12)
    throw Error("--tick", "must be in (0, 0.1] s (the control rate), got " + std::to_string(options_.tick));
  if (!(options_.loss >= 0.0) || !(options_.loss < 1.0))
    throw Error("--loss", "must be in [0, 1), got " + std::to_string(options_.loss));
  if (!(options_.rate >= 0.0)) throw Error("--rate", "must be >= 0 (0: as fast as the lockstep allows)");
  if (options_.clock == ClockMode::kWall && !(options_.rate > 0.0))
    throw Error("--rate", "must be > 0 with the wall clock (mission seconds per wall second)");
  fleet_.set_team(team.agents(), team.collector_flags(), team.links);
  last_.assign(static_cast<std::size_t>(team.agents()), Reply{});
  for (AgentId a : ids<AgentId>(team.agents())) {  // until the agent says otherwise: the plan's role, its start
    Reply& r = last_[a.index()];
    r.agent = static_cast<int16_t>(a.value());
    r.role = r.report.role = team.assignment(a).collector ? RoleKind::kCollector : RoleKind::kWorker;
    r.pose = team.start_pose(a);
  }
  replied_.assign(static_cast<std::size_t>(team.agents()), 0);
  killed_.assign(static_cast<std::size_t>(team.agents()), 0);
  restarted_.assign(static_cast<std::size_t>(team.agents()), 0);
  for (const Kill& k : options_.restarts)
    if (k.agent < 0 || k.agent >= team.agents())
      throw Error("--restart",
                  "agent " + std::to_string(k.agent) + " is not in the team of " + std::to_string(team.agents()));
  pid_.assign(static_cast<std::size_t>(team.agents()), 0);
  for (const Kill& k : options_.kills)
    if (k.agent < 0 || k.agent >= team.agents())
      throw Error("--kill",
                  "agent " + std::to_string(k.agent) + " is not in the team of " + std::to_string(team.agents()));
  held_.reserve(kHeld);
  current_.reserve(kHeld);
  inbox_.reserve(1024);
  limit_ = options_.time_limit > 0 ? options_.time_limit : time_limit(team);
  measured_.assign(oc().goals().size(), 0);
}

LockstepMaster::~LockstepMaster() = default;

// Kills agent `a`'s process, has it started again (--rejoin: from its
// journal) and waits for its READY, re-announcing the plan meanwhile.
void LockstepMaster::restart(int a, ShutdownSignal* signal) {
  const std::size_t i = static_cast<std::size_t>(a);
  const int32_t old = pid_[i];
  if (options_.kill_agent)
    options_.kill_agent(a);
  else if (old > 0)
    ::kill(static_cast<pid_t>(old), SIGKILL);
  restarted_[i] = 1;
  if (options_.respawn) options_.respawn(a);
  const auto t0 = Clock::now();
  auto last_announce = Clock::now() - std::chrono::seconds(1);
  for (;;) {
    if (seconds_since(last_announce) > 0.2) {
      PlanAnnounce p;
      p.digest = digest_, p.agents = team_.agents(), p.params = team_.params;
      p.tick = options_.tick, p.loss = options_.loss, p.loss_seed = options_.loss_seed;
      p.clock = options_.clock, p.rate = 1.0, p.robots = options_.robots;
      fleet_.publish(p);
      last_announce = Clock::now();
    }
    fleet_.handle(20);
    absorb(fleet_, held_, link_);
    bool ready = false;
    for (const Reply& r : fleet_.replies())
      if (r.tick == -1 && r.agent == a && r.status == ReplyStatus::kReady && r.pid > 0 && r.pid != old)
        ready = true, pid_[i] = r.pid;
    fleet_.replies().clear();
    if (ready) return;
    if (seconds_since(t0) > options_.ready_timeout_s || signalled(signal))
      throw Error(
          "lockstep",
          "agent " + std::to_string(a) + " did not come back READY after its restart" +
              (signalled(signal) ? " before the stop"
                                 : " within " + std::to_string(static_cast<int>(options_.ready_timeout_s)) + " s"));
  }
}

bool LockstepMaster::oc_role_dead(int agent) const {
  return static_cast<const OcRole&>(*oc_.role).declared_dead_at(AgentId(agent)) >= 0;
}

void LockstepMaster::collect_replies(int64_t tick, ReplyStatus want, double timeout_s, ShutdownSignal* signal) {
  std::size_t missing = 0;
  for (std::size_t a = 0; a < replied_.size(); ++a) replied_[a] = killed_[a], missing += !killed_[a];
  ended_seen_ = false;
  const auto t0 = Clock::now();
  auto last_announce = Clock::now() - std::chrono::seconds(1);
  while (missing > 0) {
    if (tick < 0 && seconds_since(last_announce) > 0.2) {  // the plan, again, for those that have not answered
      PlanAnnounce p;
      p.digest = digest_, p.agents = team_.agents(), p.params = team_.params;
      p.tick = options_.tick, p.loss = options_.loss, p.loss_seed = options_.loss_seed;
      p.clock = options_.clock, p.rate = options_.clock == ClockMode::kWall ? options_.rate : 1.0;
      p.robots = options_.robots;
      fleet_.publish(p);
      last_announce = Clock::now();
    }
    fleet_.handle(tick < 0 ? 50 : 5);
    absorb(fleet_, held_, link_);
    for (Reply& r : fleet_.replies()) {
      if (r.tick != tick) continue;
      const std::size_t a = static_cast<std::size_t>(r.agent);
      if (r.status == ReplyStatus::kRefused)
        throw Error("agent " + std::to_string(r.agent),
                    "refused the plan: its plan files differ from the OC's (see its log)");
      if (r.status != want || replied_[a]) continue;
      replied_[a] = 1, --missing;
      if (r.status == ReplyStatus::kReady) pid_[a] = r.pid;
      if (r.path_revision == last_[a].path_revision && r.path.empty()) r.path.swap(last_[a].path);
      for (int32_t g : r.measured_goals) count_measured(measured_, g);
      if (options_.observe)
        for (int32_t g : r.measured_goals) events_.measured.push_back(MeasuredEvent{g, r.agent, tick * options_.tick});
      last_[a] = std::move(r);
    }
    fleet_.replies().clear();
    if (missing > 0 && options_.ended) {
      // An agent whose process ended and that still owes this reply. What
      // it sent before it ended (a refusal of the plan) is read for a
      // moment first: that is the better line.
      std::string gone;
      int shown = 0, count = 0;
      for (const auto& [a, status] : options_.ended()) {
        if (a < 0 || static_cast<std::size_t>(a) >= replied_.size() || replied_[static_cast<std::size_t>(a)]) continue;
        ++count;
        if (shown++ < 10)
          gone += (gone.empty() ? "" : ", ") + std::to_string(a) + " (status " + std::to_string(status) + ")";
      }
      if (count > 10) gone += ", ...";
      if (count == 0) {
        ended_seen_ = false;
      } else if (!ended_seen_) {
        ended_seen_ = true, ended_seen_at_ = Clock::now();
      } else if (seconds_since(ended_seen_at_) > kEndedGrace_s) {
        throw Error("lockstep",
                    std::to_string(count) + " agent process(es) ended before " +
                        (tick < 0 ? std::string("saying READY") : "replying to tick " + std::to_string(tick)) + ": " +
                        gone + " (see their output above)");
      }
    }
    if (missing > 0 && (seconds_since(t0) > timeout_s || signalled(signal))) {
      std::string who;
      int shown = 0;
      for (std::size_t a = 0; a < replied_.size(); ++a)
        if (!replied_[a] && shown++ < 10) who += (who.empty() ? "" : ", ") + std::to_string(a);
      if (missing > 10) who += ", ...";
      throw Error("lockstep",
                  std::to_string(missing) + " agent(s) (" + who + ") did not " +
                      (tick < 0 ? "answer the plan announcement" : "reply to tick " + std::to_string(tick)) +
                      (signalled(signal) ? " before the stop"
                                         : " within " + std::to_string(static_cast<int>(timeout_s)) + " s"));
    }
  }
}

void LockstepMaster::start(ShutdownSignal* signal) {
  collect_replies(-1, ReplyStatus::kReady, options_.ready_timeout_s, signal);
  started_ = Clock::now();
  if (options_.clock == ClockMode::kWall) {
    // Every agent hears the start before it comes (a replay takes the recorded one).
    start_us_ = options_.start_us > 0 ? options_.start_us : fleet_.clock().now_us() + 200000;
    fleet_.publish(clock_tick(0, 0.0, start_us_));
    clock_said_ = Clock::now();
  }
}

bool LockstepMaster::tick_wall(ShutdownSignal* signal) {
  // Wait for the next step's wall time, taking messages meanwhile.
  const double target = tick_ * options_.tick;
  for (;;) {
    const double t = static_cast<double>(fleet_.clock().now_us() - start_us_) * 1e-6 * options_.rate;
    if (t >= target) break;
    if (signalled(signal)) throw Error("lockstep", "stopped by a signal at t = " + std::to_string(t) + " s");
    const auto w0 = Clock::now();
    fleet_.handle(std::clamp(static_cast<int>((target - t) / options_.rate * 1000.0), 0, 20));
    wait_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - w0).count();
    absorb(fleet_, held_, link_);
  }
  if (seconds_since(clock_said_) > 1.0) {  // the start again, for an agent that missed it
    fleet_.publish(clock_tick(tick_, now(), start_us_));
    clock_said_ = Clock::now();
  }
  fleet_.handle(0);
  absorb(fleet_, held_, link_);
  const double t = static_cast<double>(fleet_.clock().now_us() - start_us_) * 1e-6 * options_.rate;
  wall_now_ = t;
  const auto o0 = Clock::now();
  Role& oc_role = *oc_.role;
  oc_.motion->update(t);
  current_.swap(held_);
  held_.clear();
  gather_inbox(current_, oc_role.id(), oc_.motion->pose(), gate_, link_, inbox_);
  outbox_.clear();
  oc_role.control(t, inbox_.data(), inbox_.size(), outbox_);
  for (std::size_t i = 0; i < outbox_.size(); ++i) {
    outbox_[i].h.seq = seq_++;
    outbox_[i].h.tick = -1;
    fleet_.publish(outbox_[i]);
  }
  observe(t, true);
  link_.sent += static_cast<int64_t>(outbox_.size());
  messages_ += static_cast<int64_t>(outbox_.size());
  oc_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - o0).count();
  ++tick_;
  // Done once every goal is resolved and two seconds of mission time more
  // (for the last acks: there are no replies to say they landed).
  if (oc().done() && done_at_ < 0) done_at_ = t;
  return !(done_at_ >= 0 && t - done_at_ > 2.0) && t < limit_;
}

bool LockstepMaster::tick(ShutdownSignal* signal) {
  if (finished_) return false;
  if (options_.clock == ClockMode::kWall) return tick_wall(signal);
  const int64_t k = tick_;
  const double t = k * options_.tick;
  if (options_.rate > 0.0) {
    const auto at =
        started_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t / options_.rate));
    const auto w0 = Clock::now();
    if (at > w0) {
      if (signal ? signal->wait_until(at) : (std::this_thread::sleep_until(at), false))
        throw Error("lockstep", "stopped by a signal at t = " + std::to_string(t) + " s");
    }
    wait_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - w0).count();
  }
  // Agents killed now (--kill): SIGKILL to their processes, before they
  // hear this tick; their last replies (a report tick's: their custody)
  // stand for them from now on.
  for (const Kill& kill : options_.kills) {
    const std::size_t a = static_cast<std::size_t>(kill.agent);
    if (killed_[a] || t < kill.at - 1e-9) continue;
    if (options_.kill_agent)
      options_.kill_agent(kill.agent);
    else if (pid_[a] > 0)
      ::kill(static_cast<pid_t>(pid_[a]), SIGKILL);
    killed_[a] = 1;
  }
  for (const Kill& r : options_.restarts) {
    const std::size_t a = static_cast<std::size_t>(r.agent);
    if (!killed_[a] && !restarted_[a] && t >= r.at - 1e-9) restart(r.agent, signal);
  }
  bool report = false;
  for (int c = next_check_; c < team_.params.cycles && t >= (c + 1) * team_.period; ++c) report = true;
  for (const Kill& kill : options_.kills)
    if (!killed_[static_cast<std::size_t>(kill.agent)] && t + options_.tick >= kill.at - 1e-9) report = true;
  const auto p0 = Clock::now();
  Tick tick = clock_tick(k, t, 0);
  tick.sent_before = sent_before_, tick.commands_before = commands_before_, tick.report = report;
  tick.expect = expect_;
  fleet_.publish(tick);
  publish_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - p0).count();

  // The OC's own role, as any agent: every message of the tick before first.
  const auto w0 = Clock::now();
  while (count_tick(held_, k) < static_cast<std::size_t>(sent_before_)) {
    if (seconds_since(w0) > options_.reply_timeout_s)
      throw Error("lockstep", "tick " + std::to_string(k) + ": " + std::to_string(count_tick(held_, k)) + " of the " +
                                  std::to_string(sent_before_) + " messages of the tick before reached the OC");
    fleet_.handle(5);
    absorb(fleet_, held_, link_);
  }
  inbox_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - w0).count();
  const auto o0 = Clock::now();
  Role& oc_role = *oc_.role;
  oc_.motion->update(t);
  int64_t late = 0;
  take_tick(held_, current_, k, late);
  gather_inbox(current_, oc_role.id(), oc_.motion->pose(), gate_, link_, inbox_);
  outbox_.clear();
  oc_role.control(t, inbox_.data(), inbox_.size(), outbox_);
  for (std::size_t i = 0; i < outbox_.size(); ++i) {
    outbox_[i].h.seq = seq_++;
    outbox_[i].h.tick = k;
    fleet_.publish(outbox_[i]);
  }
  if (options_.observe) observe(t, false);
  link_.sent += static_cast<int64_t>(outbox_.size());
  oc_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - o0).count();

  const auto r0 = Clock::now();
  collect_replies(k, ReplyStatus::kStepped, options_.reply_timeout_s, signal);
  wait_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - r0).count();
  int64_t sent = static_cast<int64_t>(outbox_.size()), commands = 0;
  // What each agent is to receive of this tick's messages (the next tick's
  // expect): an agent with its own links' keys takes only those.
  expect_.assign(static_cast<std::size_t>(team_.agents()), 0);
  auto count_for = [&](int16_t sender, int16_t dest) {
    team_.links.receivers(sender, dest, receivers_);
    for (int16_t r : receivers_)
      if (r >= 0) ++expect_[static_cast<std::size_t>(r)];
  };
  for (std::size_t i = 0; i < outbox_.size(); ++i) count_for(kOc, outbox_[i].h.dest);
  for (const Reply& r : last_) {
    if (killed_[static_cast<std::size_t>(r.agent)]) continue;  // its last reply is of a tick before
    for (int16_t d : r.dests) count_for(r.agent, d);
    sent += r.sent;
    commands += r.commands;
    if (r.incomplete > 0 || r.late > 0)
      throw Error("lockstep", "agent " + std::to_string(r.agent) + " stepped tick " + std::to_string(k) +
                                  (r.incomplete > 0 ? " without every message of the tick before"
                                                    : " after a message of an earlier tick came too late") +
                                  " (lost or held up on this host): the run would differ from one in a single process");
  }
  if (late > 0)
    throw Error("lockstep", "the OC's role stepped tick " + std::to_string(k) +
                                " after a message of an earlier tick came too late: the run would differ from one in a "
                                "single process");
  sent_before_ = static_cast<int32_t>(sent);
  commands_before_ = static_cast<int32_t>(commands);
  messages_ += sent;
  // Conservation at every cycle's end, from the agents' own custody.
  while (next_check_ < team_.params.cycles && t >= (next_check_ + 1) * team_.period) {
    keys_.clear();
    for (const Reply& r : last_) keys_.insert(keys_.end(), r.keys.begin(), r.keys.end());
    check_conservation(oc(), measured_, keys_, t);
    ++next_check_;
  }
  ++tick_;
  // Done when every goal is resolved and every ack has landed (no agent
  // still holds a copy of something the OC already has).
  bool held = false;
  for (const Reply& r : last_)
    held = held || (!gone(r.agent) && (r.carried > 0 || r.notices > 0 || still_owes(r.report, oc())));
  return !(oc().done() && !held) && t < limit_;
}

// What the views need from the radio traffic the OC has just taken in (all of
// it, as the bus carries it, the OC's own messages included, not only what
// reached the OC): custody hand-overs (an ack of at least one item: the acker
// took them from the acked), and with the wall clock, where each agent was
// when it last sent something.
void LockstepMaster::observe(double t, bool wall) {
  auto handovers = [&](const Message& m) {
    if (m.h.kind == Kind::kAck && m.ack.count > 0 && m.h.dest != kBroadcast)
      events_.handovers.push_back(HandoverEvent{m.h.dest, m.h.sender, m.ack.count, t});
  };
  for (const Message& m : current_) {
    if (options_.observe) handovers(m);
    if (!wall || m.h.sender < 0 || m.h.sender >= team_.agents()) continue;
    Reply& r = last_[static_cast<std::size_t>(m.h.sender)];
    r.pose = m.h.pos;
    r.report.requests = m.h.request;
    if (m.h.kind == Kind::kState) {
      r.role = m.state.role;
      r.carried = m.state.carried, r.notices = m.state.notices;
      r.report.pending = m.state.pending, r.report.measured = m.state.measured;
    }
  }
}

void LockstepMaster::take_events(ViewEvents& into) {
  into.measured.swap(events_.measured);
  into.handovers.swap(events_.handovers);
  events_.measured.clear();
  events_.handovers.clear();
}

double LockstepMaster::agents_step_ms() const {
  double us = 0.0;
  for (const Reply& r : last_) us += static_cast<double>(r.step_us);
  return us / 1000.0;
}

RunOutcome LockstepMaster::finish() {
  RunOutcome out;
  if (!finished_) {
    Tick done = clock_tick(tick_, now(), start_us_);
    done.sent_before = sent_before_, done.done = true;
    for (int i = 0; i < 3; ++i) fleet_.publish(done);
    finished_ = true;
  }
  out.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - started_).count();
  out.ticks = tick_;
  out.end_s = options_.clock == ClockMode::kWall ? now() : (tick_ - 1) * options_.tick;
  if (!oc().done() && options_.robots) out.closed_at_end = static_cast<int64_t>(oc().close(out.end_s));
  out.completed = oc().done();
  for (const Reply& r : last_) {
    AgentSummary s;
    s.id = r.agent, s.role = r.role, s.report = r.report, s.link = r.link, s.auth = r.auth, s.carried = r.carried;
    s.contacts = r.contacts;
    s.robot.faults = r.robot_faults;
    s.delivered = oc().delivered_by(AgentId(r.agent));
    out.agents.push_back(s);
  }
  out.oc_link = link_;
  out.oc_link.bad = fleet_.dropped();
  out.oc_auth = fleet_.rejected();
  out.messages = messages_;
  out.invalid_items = oc().invalid_items();
  out.duplicate_items = oc().duplicate_items();
  out.recovered = oc().recovered();
  out.overridden = oc().overridden();
  out.kills = options_.kills;
  out.restarts = options_.restarts;
  for (int16_t a : oc().dead()) out.declared_dead.emplace_back(a, oc().declared_dead_at(AgentId(a)));
  out.revoked = revocations(oc());
  if (!out.completed) {
    out.failure = "mission not finished at t = " + std::to_string(out.end_s) + " s (limit " + std::to_string(limit_) +
                  " s): " + std::to_string(oc().requested() - oc().resolved_count()) + " of " +
                  std::to_string(oc().requested()) + " goals unresolved";
    return out;
  }
  out.result = mission::mission_result(oc().goals(), team_.params.cycles, team_.period, out.wall_ms, team_.areas);
  return out;
}

}  // namespace agent
}  // namespace gather
