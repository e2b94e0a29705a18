#pragma once
// Agents, collectors and goals are named by 0-based ids: an agent 0..N-1 of
// the team, a collector 0..N_c-1 (its route has the same index; the plan
// makes collector k agent k, but the two are different things: a worker
// delivers to a collector, and its messages go to that collector's agent),
// a goal 0.. of the mission (cycle-major, global: goal id = its index in the
// requests drawn). Id<Tag> keeps them apart, so that a collector is not
// looked up as an agent, nor a goal's id as its place in a worker's request,
// without saying so; IdTable<Id, T> is a table indexed by one kind of id
// only. (Segments are named by their label 1..N_w: segment_id.hpp.)
//
// Ids stay plain integers where they leave the program: the plan file, the
// CSVs, the journal and the messages (gather_agent/messages.hpp, the radio's addresses,
// which also name the OC and "everyone"); the code that reads or writes
// those converts at the edge.
#include <cstddef>
#include <ostream>
#include <string>

#include "gather_core/id_table.hpp"

namespace gather {

template <class Tag>
class Id {
 public:
  constexpr Id() = default;  // none (-1)
  constexpr explicit Id(int value) : value_(value) {}
  // The id at position `index` of a table of them.
  static constexpr Id at_index(std::size_t index) { return Id(static_cast<int>(index)); }

  constexpr int value() const { return value_; }        // 0..; -1 = none
  constexpr bool valid() const { return value_ >= 0; }  // names one
  // Names one of the ids 0..n-1.
  constexpr bool within(int n) const { return value_ >= 0 && value_ < n; }
  // Position in a table of them; only for a valid id.
  constexpr std::size_t index() const { return static_cast<std::size_t>(value_); }

  friend constexpr bool operator==(Id a, Id b) { return a.value_ == b.value_; }
  friend constexpr bool operator!=(Id a, Id b) { return a.value_ != b.value_; }
  friend constexpr bool operator<(Id a, Id b) { return a.value_ < b.value_; }

 private:
  int value_ = -1;
};

struct AgentTag {
  static constexpr const char* kName = "agent";
};
struct CollectorTag {
  static constexpr const char* kName = "collector";
};
struct GoalTag {
  static constexpr const char* kName = "goal";
};
using AgentId = Id<AgentTag>;          // an agent of the team, 0..N-1
using CollectorId = Id<CollectorTag>;  // a collector and its route, 0..N_c-1; none: the OC
using GoalId = Id<GoalTag>;            // a goal of the mission, 0.. cycle-major

template <class Tag>
std::string to_string(Id<Tag> id) {
  return std::string(Tag::kName) + " " + std::to_string(id.value());
}
template <class Tag>
std::ostream& operator<<(std::ostream& out, Id<Tag> id) {
  return out << to_string(id);
}

template <class T>
using PerAgent = IdTable<AgentId, T>;
template <class T>
using PerCollector = IdTable<CollectorId, T>;

// The ids 0..n-1, for `for (AgentId a : ids<AgentId>(n))`.
template <class IdT>
constexpr IdRange<IdT> ids(int n) {
  return IdRange<IdT>(0, n);
}

}  // namespace gather
