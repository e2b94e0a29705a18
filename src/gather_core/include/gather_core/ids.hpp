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
#include <cassert>
#include <cstddef>
#include <initializer_list>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

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

// One T per id 0..size()-1, indexed by that kind of id only. Grows like the
// vector it holds (tables built entry by entry: routes, assignments).
template <class IdT, class T>
class IdTable {
 public:
  IdTable() = default;
  explicit IdTable(int n, const T& fill = T{}) : values_(n > 0 ? static_cast<std::size_t>(n) : 0, fill) {}
  explicit IdTable(std::vector<T> values) : values_(std::move(values)) {}
  IdTable(std::initializer_list<T> values) : values_(values) {}  // entry 0 first

  std::size_t size() const { return values_.size(); }
  int count() const { return static_cast<int>(values_.size()); }
  bool empty() const { return values_.empty(); }
  // The entry of `id`, which must be in 0..size()-1.
  T& operator[](IdT id) {
    assert(id.within(count()));
    return values_[id.index()];
  }
  const T& operator[](IdT id) const {
    assert(id.within(count()));
    return values_[id.index()];
  }
  T& front() { return values_.front(); }
  const T& front() const { return values_.front(); }
  T& back() { return values_.back(); }
  const T& back() const { return values_.back(); }

  void push_back(T value) { values_.push_back(std::move(value)); }
  template <class... Args>
  T& emplace_back(Args&&... args) {
    return values_.emplace_back(std::forward<Args>(args)...);
  }
  void reserve(std::size_t n) { values_.reserve(n); }
  void clear() { values_.clear(); }
  void assign(int n, const T& fill) { values_.assign(n > 0 ? static_cast<std::size_t>(n) : 0, fill); }

  typename std::vector<T>::iterator begin() { return values_.begin(); }
  typename std::vector<T>::iterator end() { return values_.end(); }
  typename std::vector<T>::const_iterator begin() const { return values_.begin(); }
  typename std::vector<T>::const_iterator end() const { return values_.end(); }
  const std::vector<T>& values() const { return values_; }

  friend bool operator==(const IdTable& a, const IdTable& b) { return a.values_ == b.values_; }
  friend bool operator!=(const IdTable& a, const IdTable& b) { return a.values_ != b.values_; }

 private:
  std::vector<T> values_;
};
template <class T>
using PerAgent = IdTable<AgentId, T>;
template <class T>
using PerCollector = IdTable<CollectorId, T>;

// The ids 0..n-1, for `for (AgentId a : ids<AgentId>(n))`.
template <class IdT>
class IdRange {
 public:
  class iterator {
   public:
    constexpr explicit iterator(int value) : value_(value) {}
    constexpr IdT operator*() const { return IdT(value_); }
    constexpr iterator& operator++() {
      ++value_;
      return *this;
    }
    friend constexpr bool operator!=(iterator a, iterator b) { return a.value_ != b.value_; }

   private:
    int value_;
  };
  constexpr explicit IdRange(int n) : n_(n > 0 ? n : 0) {}
  constexpr iterator begin() const { return iterator(0); }
  constexpr iterator end() const { return iterator(n_); }

 private:
  int n_;
};
template <class IdT>
constexpr IdRange<IdT> ids(int n) {
  return IdRange<IdT>(n);
}

}  // namespace gather
