#include "gather_agent/roles/collector_role.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

// [s] the delay measured from the robot's position between two waypoints
// counts once it is this much larger than the one measured at the waypoints
// (an ideal base's position gives float noise only).
constexpr double kPositionDelayFloor = 0.05;

}  // namespace

CollectorRole::CollectorRole(TeamSetup& team, AgentId agent, MotionBackend& motion)
    : Role(static_cast<int16_t>(agent.value()), motion),
      team_(team),
      collector_(team.assignment(agent).delivers_to),
      route_(team.routes[team.assignment(agent).delivers_to]),
      custody_(team.params.data_capacity, team.params.notice_capacity) {
  const plan::CollectorRoute& r = team.plan.file.routes[collector_];
  for (const plan::MeetingArea& m : r.meetings) {
    const AgentId w = team.worker_of_segment(m.segment);
    if (!w.valid() || team.assignment(w).delivers_to != collector_)
      throw Error(team.plan.source.empty() ? "plan" : team.plan.source,
                  to_string(collector_) + " meets " + to_string(m.segment) + ", whose worker is not its own");
    workers_.push_back(Served{static_cast<int16_t>(w.value()), m.arc_m, -1});
  }
  const std::size_t g = static_cast<std::size_t>(team.params.goals_per_request);
  parts_.resize(std::max<std::size_t>(1, (g + kRequestPartGoals - 1) / kRequestPartGoals));
  acks_.reserve(kMaxBatch);
  dead_.reserve(kMaxDead);
  legs_.resize(std::max<std::size_t>(1, route_.waypoints().size()));
  if (motion.max_legs() < legs_.size())
    throw Error(to_string(agent), "its motion backend takes " + std::to_string(motion.max_legs()) +
                                      " waypoints a command, its route has " + std::to_string(legs_.size()));
  next_beacon_ = team.params.beacon_period * static_cast<double>(agent.value() % 10) / 10.0;
  next_depart_ = route_.schedule().next_departure(0.0);
  counters_.role = RoleKind::kCollector;
  counters_.id = agent.value();
}

RoleReport CollectorRole::report() const {
  RoleReport r = counters_;
  r.requests = newest_request();
  r.dead_known = static_cast<int64_t>(dead_.size());
  r.legs = legs_stats_.legs(), r.legs_late = legs_stats_.late();
  r.late_median_s = legs_stats_.median_late(), r.late_max_s = legs_stats_.max_late();
  r.loops = loop_stats_.legs();
  r.loop_late_median_s = loop_stats_.median_late(), r.loop_late_max_s = loop_stats_.max_late();
  r.refused_revoked = refused_revoked();
  return r;
}

void CollectorRole::restore(const DataItem* items, std::size_t n, const Progress& p, double now) {
  for (std::size_t i = 0; i < n; ++i)
    if (custody_.put(items[i]) == Custody::Put::kFull) ++counters_.refused_full;
  dead_.assign(p.dead.begin(), p.dead.end());
  revoked_ = p.revoked;
  if (std::find(dead_.begin(), dead_.end(), id_) != dead_.end()) retired_ = true, motion_.stop(now);
  // The passes ahead of it, not those behind: it hands requests on from here.
  timetable_prev_ = now;
  if (retired_ || route_.idle()) return;
  // Back on the timetable: the rest of the loop the timetable drives now
  // (from its next waypoint), or the next loop.
  const double depart = route_.schedule().last_departure(now);
  const double into = now - depart;
  const std::vector<double>& arc = route_.arcs();
  if (into < route_.period()) {
    std::size_t first = 1;
    while (first + 1 < arc.size() && arc[first] / route_.speed() <= into) ++first;
    command_loop(depart, first, now);
  } else {
    next_depart_ = route_.schedule().next_departure(now);
  }
}

CollectorRole::Served* CollectorRole::served(int16_t agent) {
  for (Served& w : workers_)
    if (w.agent == agent) return &w;
  return nullptr;
}

void CollectorRole::on_request(const RequestPart& part, double now) {
  if (learn_dead(part) && std::find(dead_.begin(), dead_.end(), id_) != dead_.end()) {
    retired_ = true;  // declared dead: the plan was repaired around it
    motion_.stop(now);
  }
  if (part.request < request_id_ || part.request >= team_.params.cycles) return;
  if (part.parts == 0 || part.parts > kMaxRequestParts || part.part >= part.parts || part.count > kRequestPartGoals)
    return;
  if (part.parts > parts_.size()) parts_.resize(part.parts);  // a larger request than the scenario's
  if (part.request > request_id_) request_id_ = part.request, seen_ = 0, complete_ = false;
  if ((seen_ >> part.part) & 1) return;
  seen_ |= 1ull << part.part;
  parts_[part.part] = part;
  complete_ = seen_ == (part.parts >= 64 ? ~0ull : ((1ull << part.parts) - 1));
}

void CollectorRole::hand_request(Served& w, double now, Outbox& out) {
  if (!complete_ || (w.handed >= request_id_ && w.handed_dead >= known_declarations())) return;
  const uint16_t parts = parts_[0].parts;
  for (uint16_t p = 0; p < parts; ++p)
    if (Message* m = send(out, Kind::kRequest, w.agent, now)) {
      m->request = parts_[p];
      stamp_dead(m->request);
    }
  w.handed = request_id_;
  w.handed_dead = known_declarations();
}

double CollectorRole::planned_at(std::size_t vertex) const {
  return loop_depart_ + route_.arcs()[vertex] / route_.speed();
}

void CollectorRole::command_loop(double depart, std::size_t first, double now) {
  const std::vector<Point2>& w = route_.waypoints();
  loop_depart_ = depart, loop_first_ = first;
  std::size_t n = 0;
  // The last waypoint is the OC: anywhere near it will do (robots wait there).
  for (std::size_t v = first; v < w.size(); ++v)
    legs_[n++] = Waypoint{w[v], planned_at(v), v + 1 == w.size() ? team_.params.protocol.place_tolerance_m : 0.0};
  motion_.go(legs_.data(), n, now);
  legs_seen_ = 0;
  driving_ = true;
  next_depart_ = route_.schedule().next_departure(depart + route_.period());
}

void CollectorRole::drive(double now) {
  if (route_.idle()) {  // no workers to meet: it waits where it is, next to the OC
    delay_ = 0.0;
    timetable_now_ = now;
    return;
  }
  const std::size_t n = route_.waypoints().size() - loop_first_;  // waypoints of the loop commanded
  if (driving_)
    for (; legs_seen_ < std::min(motion_.legs_done(), n); ++legs_seen_)
      legs_stats_.add(motion_.arrived_at(legs_seen_) - planned_at(loop_first_ + legs_seen_));
  if (driving_) {
    switch (motion_.state()) {
      case NavState::kReached:
        driving_ = false;
        loop_stats_.add(motion_.arrived_at(n - 1) - planned_at(route_.waypoints().size() - 1));
        break;
      case NavState::kFailed: {
        // A waypoint it cannot reach: on to the next one (the last, the OC:
        // again until it gets there).
        ++counters_.nav_failures;
        const std::size_t skip = std::min(motion_.legs_done() + 1, n - 1);
        command_loop(loop_depart_, loop_first_ + skip, now);
        break;
      }
      case NavState::kIdle:  // stopped under it (a restart of its robot): the rest of the loop
        command_loop(loop_depart_, loop_first_ + std::min(motion_.legs_done(), n - 1), now);
        break;
      default: break;
    }
  }
  if (!driving_ && now >= next_depart_) {
    // The latest loop of the timetable that has started and was not driven
    // yet: a collector back late drives on at once, on a later loop if it
    // missed the start of one.
    command_loop(std::max(next_depart_, route_.schedule().last_departure(now)), 1, now);
  }
  // Its delay: how late it reached its last waypoint, or how overdue the
  // next one is, or (between the two) how far its position on the way is
  // behind the timetable's.
  double d = 0.0;
  if (driving_) {
    const std::size_t done = std::min(motion_.legs_done(), route_.waypoints().size() - loop_first_);
    if (done > 0) d = motion_.arrived_at(done - 1) - planned_at(loop_first_ + done - 1);
    const std::size_t next = loop_first_ + done;
    if (next < route_.waypoints().size()) {
      if (now > planned_at(next)) d = std::max(d, now - planned_at(next));
      const Point2 a = route_.waypoints()[next - 1], b = route_.waypoints()[next], p = motion_.pose();
      const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
      const double f = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 1.0;
      const double at_pos = planned_at(next - 1) + f * (planned_at(next) - planned_at(next - 1));
      if (now - at_pos > d + kPositionDelayFloor) d = now - at_pos;
    }
  }
  delay_ = d;
  timetable_now_ = std::max(timetable_prev_, now - d);
}

void CollectorRole::step(double now, const Message* const* inbox, std::size_t n, Outbox& out) {
  if (retired_) return hand_in(team_, now, inbox, n, out, custody_);
  drive(now);
  for (std::size_t i = 0; i < n; ++i) {
    const Message& m = *inbox[i];
    if (Served* w = served(m.h.sender)) w->heard_at = now;
    if (m.h.dest != id_ && m.h.dest != kBroadcast) continue;
    switch (m.h.kind) {
      case Kind::kRequest:
        if (m.h.sender == kOc) on_request(m.request, now);
        break;
      case Kind::kAck:
        if (m.h.sender == kOc && m.h.dest == id_)
          custody_.acked(m.ack.keys, std::min<std::size_t>(m.ack.count, kMaxBatch));
        break;
      case Kind::kData: {
        Served* w = served(m.h.sender);
        if (!w || m.h.dest != id_) break;
        acks_.clear();
        const std::size_t count = std::min<std::size_t>(m.data.count, kMaxBatch);
        for (std::size_t k = 0; k < count; ++k) {
          DataItem item = m.data.items[k];
          if (item.kind == ItemKind::kMeasured && item.picked_up_by < 0)
            item.picked_up_by = id_, item.picked_up_at = now;
          if (custody_.put(item) == Custody::Put::kFull) {
            ++counters_.refused_full;  // not acked: the worker keeps it
            continue;
          }
          acks_.push_back(item.key);
        }
        if (Message* a = send(out, Kind::kAck, w->agent, now)) {
          a->ack.count = static_cast<uint16_t>(acks_.size());
          std::copy(acks_.begin(), acks_.end(), a->ack.keys);
        }
        // A worker that lacks the request it should have (it missed the
        // meeting area) gets it now.
        if ((m.h.request < request_id_ || m.h.dead < known_declarations()) && w->handed >= request_id_)
          w->handed = -1, hand_request(*w, now, out);
        break;
      }
      case Kind::kState: {
        Served* w = served(m.h.sender);
        // One that asks (a hello: its request is due) gets it now, even
        // before this loop's pass handed it (it missed request 0 at the
        // start, or the hand-over at the pass was lost); a beacon only
        // after the pass.
        if (w && (m.h.request < request_id_ || m.h.dead < known_declarations()) &&
            (m.h.dest == id_ || w->handed >= request_id_))
          w->handed = -1, hand_request(*w, now, out);
        break;
      }
    }
  }
  // The request goes to each worker as the collector passes its meeting
  // area: where its timetable, shifted by its delay, is.
  for (Served& w : workers_)
    if (route_.next_time_at(w.meeting_arc, timetable_prev_ < 0 ? 0.0 : timetable_prev_) <= timetable_now_)
      hand_request(w, now, out);
  timetable_prev_ = timetable_now_;

  // Deliver while inside the coverage; say hello when entering it (the OC
  // passes on its newest request).
  const bool in_contact = team_.linked(motion_.pose(), team_.world.scenario.oc);
  if (in_contact && custody_.size() > 0) {
    DataBatch batch;
    if (custody_.due(now, team_.params.resend_after, !contact_prev_, batch) > 0)
      if (Message* m = send(out, Kind::kData, kOc, now)) m->data = batch;
  }
  auto state = [&](int16_t dest) {
    if (Message* m = send(out, Kind::kState, dest, now)) {
      m->state = StateReport{};
      m->state.role = RoleKind::kCollector;
      m->state.carried = static_cast<uint16_t>(std::min<std::size_t>(custody_.data(), 65535));
      m->state.notices = static_cast<uint16_t>(std::min<std::size_t>(custody_.notices(), 65535));
      const std::size_t k = std::min<std::size_t>(workers_.size(), kMaxHeard);
      m->state.heard_count = static_cast<uint8_t>(k);
      for (std::size_t i = 0; i < k; ++i)
        m->state.heard_agent[i] = workers_[i].agent, m->state.heard_at[i] = workers_[i].heard_at;
    }
  };
  if (in_contact && !contact_prev_) state(kOc);
  if (now >= next_beacon_) {
    state(kBroadcast);
    while (next_beacon_ <= now) next_beacon_ += team_.params.beacon_period;
  }
  contact_prev_ = in_contact;
}

}  // namespace agent
}  // namespace gather
