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

namespace gather {
namespace agent {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kHeld = 8192;  // radio messages held for the ticks to come
constexpr std::size_t kOutbox = 64;  // messages a role sends in one tick

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Wall time [us since the epoch]: what every process of a fleet on one
// host (or on NTP-synchronised robots) agrees on.
int64_t realtime_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void fnv1a(uint64_t& h, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot read (needed for the plan's digest)");
  char buf[65536];
  while (in) {
    in.read(buf, sizeof buf);
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ static_cast<uint8_t>(buf[i])) * 1099511628211ull;
  }
}

bool signalled(ShutdownSignal* s) { return s && s->wait_until(Clock::now()); }

// Moves the messages of `tick` - 1 from `held` into `current` (and drops,
// counting them, any older ones that came too late).
void take_tick(std::vector<Message>& held, std::vector<Message>& current, int64_t tick, int64_t& late) {
  current.clear();
  std::size_t keep = 0;
  for (std::size_t i = 0; i < held.size(); ++i) {
    if (held[i].h.tick == tick - 1)
      current.push_back(held[i]);
    else if (held[i].h.tick < tick - 1)
      ++late;
    else
      held[keep++] = held[i];
  }
  held.resize(keep);
  // In (sender, seq) order, as the in-process runner has them: an inbox that
  // overflows keeps the same messages whatever the arrival order.
  std::sort(current.begin(), current.end(), [](const Message& a, const Message& b) {
    return a.h.sender != b.h.sender ? a.h.sender < b.h.sender : a.h.seq < b.h.seq;
  });
}

std::size_t count_tick(const std::vector<Message>& held, int64_t tick) {
  std::size_t n = 0;
  for (const Message& m : held) n += m.h.tick == tick - 1;
  return n;
}

void absorb(LcmFleet& fleet, std::vector<Message>& held, LinkCounters& link) {
  for (const Message& m : fleet.radio()) {
    if (held.size() >= held.capacity()) {
      ++link.overflow;
      continue;
    }
    held.push_back(m);
  }
  fleet.radio().clear();
}

}  // namespace

uint64_t plan_digest(const LoadedPlan& p) {
  namespace fs = std::filesystem;
  const fs::path yaml = fs::is_directory(p.dir) ? fs::path(p.dir) / "plan.yaml" : fs::path(p.dir);
  uint64_t h = 14695981039346656037ull;
  fnv1a(h, yaml.string());
  fnv1a(h, (yaml.parent_path() / p.plan.file.labels_png).string());
  fnv1a(h, p.scenario.path);
  fnv1a(h, p.scenario.map_path);
  fnv1a(h, p.scenario.map_meta.image);
  return h;
}

static std::string seconds_text(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", s);
  return b;
}

// --- agent -----------------------------------------------------------------

LockstepAgent::LockstepAgent(LoadedPlan& plan, int id, LcmFleet& fleet)
    : plan_(plan), id_(id), fleet_(fleet), digest_(plan_digest(plan)) {
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
  try {
    team_ = std::make_unique<TeamSetup>(*world_, plan_.plan, p.params);
    gate_ = std::make_unique<RangeGate>(*team_, p.loss, p.loss_seed);
    unit_ = make_agent(*team_, id_);
    if (!journal_dir_.empty()) {
      journal_ = std::make_unique<JournalKeeper>(journal_path(journal_dir_, id_), id_, journal_run_id(team_->params));
      rejoin_state_ = journal_->open(rejoin_);
      if (rejoin_ && !rejoin_state_.matched)
        throw Error(journal_path(journal_dir_, id_), "--rejoin: no journal of this agent and mission to replay");
      // Where it was; what it held and how far it got come back at its first tick.
      if (rejoin_) unit_ = make_agent(*team_, id_, rejoin_state_.have_pose ? &rejoin_state_.pose : nullptr);
      journal_->bind(*unit_.role);
    }
  } catch (const std::exception& e) {  // its plan cannot be run as the OC asks: refuse it
    *why = e.what();
    team_.reset();
    return false;
  }
  outbox_ = std::make_unique<Outbox>(kOutbox);
  tick_s_ = p.tick;
  clock_ = p.clock;
  rate_ = p.rate;
  fleet_.set_team(p.agents);
  // A repair (a repaired plan merges segments: docs/faults.md) reads the
  // label image again from the plan directory.
  team_->reload_labels = [dir = plan_.dir]() { return mission::load_mission_plan(dir).labels; };
  std::vector<int32_t>().swap(plan_.plan.labels);
  malloc_trim(0);  // give back what loading the map and the plan used and freed
  return true;
}

bool LockstepAgent::inbox_complete(const Tick& tick) const {
  return count_tick(held_, tick.tick) >= static_cast<std::size_t>(tick.sent_before);
}

void LockstepAgent::step(const Tick& tick) {
  const auto s0 = Clock::now();
  Role& role = *unit_.role;
  unit_.motion->advance(tick.t);
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
  role.step(tick.t, inbox_.data(), inbox_.size(), out);
  if (journal_) journal_->after_step(*unit_.motion, tick.t);  // durable before its messages go out
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].h.seq = seq_++;
    out[k].h.tick = tick.tick;
    fleet_.publish(out[k]);
  }
  link_.sent += static_cast<int64_t>(out.size());
  link_.bad = fleet_.dropped();
  step_us_ += std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - s0).count();
  reply_.step_us = step_us_;
  reply_.tick = tick.tick;
  reply_.agent = static_cast<int16_t>(id_);
  reply_.status = ReplyStatus::kStepped;
  reply_.sent = static_cast<int32_t>(out.size());
  reply_.pose = unit_.motion->pose();
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
  // For the OC's views: what it measured, and its path when that changed.
  reply_.measured_goals.clear();
  if (const std::vector<int32_t>* m = role.measured_in_step())
    reply_.measured_goals.insert(reply_.measured_goals.end(), m->begin(),
                                 m->begin() + static_cast<std::ptrdiff_t>(std::min(m->size(), kReplyMaxPoints)));
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
  unit_.motion->advance(t);
  if (rejoin_) {  // a restart: what it held and how far it got, now
    rejoin_ = false;
    role.restore(rejoin_state_.custody.data(), rejoin_state_.custody.size(), rejoin_state_.progress, t);
  }
  current_.swap(held_);
  held_.clear();
  gather_inbox(current_, role.id(), unit_.motion->pose(), *gate_, link_, inbox_);
  Outbox& out = *outbox_;
  out.clear();
  role.step(t, inbox_.data(), inbox_.size(), out);
  if (journal_) journal_->after_step(*unit_.motion, t);  // durable before its messages go out
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].h.seq = seq_++;
    out[k].h.tick = -1;
    fleet_.publish(out[k]);
  }
  link_.sent += static_cast<int64_t>(out.size());
}

LockstepAgent::End LockstepAgent::run(ShutdownSignal& signal, double silence_s, std::string* why) {
  auto heard = Clock::now();
  bool have_tick = false;
  Tick pending;
  auto tick_since = Clock::now();
  for (;;) {
    if (signal.wait_until(Clock::now())) return End::kStopped;
    fleet_.handle(have_tick ? 20 : wall_start_us_ > 0 ? wall_wait_ms_ : 100);
    absorb(fleet_, held_, link_);
    if (!fleet_.plans().empty()) {
      heard = Clock::now();
      if (!team_ && !take_plan(why)) {
        Reply r;
        r.tick = -1, r.agent = static_cast<int16_t>(id_), r.status = ReplyStatus::kRefused;
        fleet_.publish(r);
        return End::kRefused;
      }
      if (next_tick_ == 0) {  // (again) READY: the OC may not have heard the last one
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
      const double t = static_cast<double>(realtime_us() - wall_start_us_) * 1e-6 * rate_;
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
    while (have_tick && (rejoin_ || inbox_complete(pending) || seconds_since(tick_since) > 5.0)) {
      if (!rejoin_ && !inbox_complete(pending)) ++incomplete_;
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

// --- master ----------------------------------------------------------------

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
  fleet_.set_team(team.agents());
  last_.assign(static_cast<std::size_t>(team.agents()), Reply{});
  for (int a = 0; a < team.agents(); ++a) {  // until the agent says otherwise: the plan's role, its start
    Reply& r = last_[static_cast<std::size_t>(a)];
    r.agent = static_cast<int16_t>(a);
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
      p.clock = options_.clock, p.rate = 1.0;
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
  return static_cast<const OcRole&>(*oc_.role).declared_dead_at(agent) >= 0;
}

void LockstepMaster::collect_replies(int64_t tick, ReplyStatus want, double timeout_s, ShutdownSignal* signal) {
  std::size_t missing = 0;
  for (std::size_t a = 0; a < replied_.size(); ++a) replied_[a] = killed_[a], missing += !killed_[a];
  const auto t0 = Clock::now();
  auto last_announce = Clock::now() - std::chrono::seconds(1);
  while (missing > 0) {
    if (tick < 0 && seconds_since(last_announce) > 0.2) {  // the plan, again, for those that have not answered
      PlanAnnounce p;
      p.digest = digest_, p.agents = team_.agents(), p.params = team_.params;
      p.tick = options_.tick, p.loss = options_.loss, p.loss_seed = options_.loss_seed;
      p.clock = options_.clock, p.rate = options_.clock == ClockMode::kWall ? options_.rate : 1.0;
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
      if (options_.observe)
        for (int32_t g : r.measured_goals) events_.measured.push_back(MeasuredEvent{g, r.agent, tick * options_.tick});
      last_[a] = std::move(r);
    }
    fleet_.replies().clear();
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
    start_us_ = realtime_us() + 200000;  // every agent hears the start before it comes
    fleet_.publish(Tick{0, 0.0, 0, false, false, start_us_});
    clock_said_ = Clock::now();
  }
}

bool LockstepMaster::tick_wall(ShutdownSignal* signal) {
  // Wait for the next step's wall time, taking messages meanwhile.
  const double target = tick_ * options_.tick;
  for (;;) {
    const double t = static_cast<double>(realtime_us() - start_us_) * 1e-6 * options_.rate;
    if (t >= target) break;
    if (signalled(signal)) throw Error("lockstep", "stopped by a signal at t = " + std::to_string(t) + " s");
    const auto w0 = Clock::now();
    fleet_.handle(std::clamp(static_cast<int>((target - t) / options_.rate * 1000.0), 0, 20));
    wait_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - w0).count();
    absorb(fleet_, held_, link_);
  }
  if (seconds_since(clock_said_) > 1.0) {  // the start again, for an agent that missed it
    fleet_.publish(Tick{tick_, now(), 0, false, false, start_us_});
    clock_said_ = Clock::now();
  }
  fleet_.handle(0);
  absorb(fleet_, held_, link_);
  const double t = static_cast<double>(realtime_us() - start_us_) * 1e-6 * options_.rate;
  wall_now_ = t;
  const auto o0 = Clock::now();
  Role& oc_role = *oc_.role;
  oc_.motion->advance(t);
  current_.swap(held_);
  held_.clear();
  gather_inbox(current_, oc_role.id(), oc_.motion->pose(), gate_, link_, inbox_);
  outbox_.clear();
  oc_role.step(t, inbox_.data(), inbox_.size(), outbox_);
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
  fleet_.publish(Tick{k, t, sent_before_, report, false, 0});
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
  oc_.motion->advance(t);
  int64_t late = 0;
  take_tick(held_, current_, k, late);
  gather_inbox(current_, oc_role.id(), oc_.motion->pose(), gate_, link_, inbox_);
  outbox_.clear();
  oc_role.step(t, inbox_.data(), inbox_.size(), outbox_);
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
  int64_t sent = static_cast<int64_t>(outbox_.size());
  for (const Reply& r : last_) {
    if (killed_[static_cast<std::size_t>(r.agent)]) continue;  // its last reply is of a tick before
    sent += r.sent;
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
  messages_ += sent;
  // Conservation at every cycle's end, from the agents' own custody.
  while (next_check_ < team_.params.cycles && t >= (next_check_ + 1) * team_.period) {
    keys_.clear();
    int64_t measured = 0;
    for (const Reply& r : last_) {
      if (r.role == RoleKind::kWorker) measured += r.report.measured;
      keys_.insert(keys_.end(), r.keys.begin(), r.keys.end());
    }
    check_conservation(oc(), measured, keys_, t);
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
    for (int i = 0; i < 3; ++i) fleet_.publish(Tick{tick_, now(), sent_before_, false, true, start_us_});
    finished_ = true;
  }
  out.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - started_).count();
  out.ticks = tick_;
  out.end_s = options_.clock == ClockMode::kWall ? now() : (tick_ - 1) * options_.tick;
  out.completed = oc().done();
  for (const Reply& r : last_) {
    AgentSummary s;
    s.id = r.agent, s.role = r.role, s.report = r.report, s.link = r.link, s.auth = r.auth, s.carried = r.carried;
    s.delivered = oc().delivered_by(r.agent);
    out.agents.push_back(s);
  }
  out.oc_link = link_;
  out.oc_link.bad = fleet_.dropped();
  out.oc_auth = fleet_.rejected();
  out.messages = messages_;
  out.invalid_items = oc().invalid_items();
  out.duplicate_items = oc().duplicate_items();
  out.recovered = oc().recovered();
  out.kills = options_.kills;
  out.restarts = options_.restarts;
  for (int16_t a : oc().dead()) out.declared_dead.emplace_back(a, oc().declared_dead_at(a));
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
