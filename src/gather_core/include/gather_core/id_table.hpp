#pragma once
// A table indexed by one kind of id only, and a run of ids, for every id type
// of the project: the 0-based AgentId, CollectorId and GoalId (ids.hpp) and
// the 1-based SegmentId (segment_id.hpp). An id type gives within(n) (names
// one of a table of n) and index() (its position in the table).
#include <cassert>
#include <cstddef>
#include <initializer_list>
#include <type_traits>
#include <utility>
#include <vector>

namespace gather {

// One T per id of a table of size() entries, indexed by that kind of id
// only. Grows like the vector it holds (tables built entry by entry: routes,
// assignments).
template <class IdT, class T>
class IdTable {
 public:
  IdTable() = default;
  explicit IdTable(int n, const T& fill = T{}) : values_(n > 0 ? static_cast<std::size_t>(n) : 0, fill) {}
  // values[0] is the first id's entry (agent 0, segment 1).
  explicit IdTable(std::vector<T> values) : values_(std::move(values)) {}
  // The entries listed, the first id's first; not for numbers, where
  // PerAgent<int> t{n, 0} would be the list {n, 0}, not n zeros.
  template <class U = T, std::enable_if_t<!std::is_arithmetic_v<U>, int> = 0>
  IdTable(std::initializer_list<T> values) : values_(values) {}

  std::size_t size() const { return values_.size(); }
  int count() const { return static_cast<int>(values_.size()); }
  bool empty() const { return values_.empty(); }
  // The entry of `id`, which must name one of the count() entries.
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

// The ids IdT(first)..IdT(end - 1), for range-for (ids(n), segment_ids(n)).
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
  constexpr IdRange(int first, int end) : first_(first), end_(end > first ? end : first) {}
  constexpr iterator begin() const { return iterator(first_); }
  constexpr iterator end() const { return iterator(end_); }

 private:
  int first_, end_;
};

}  // namespace gather
