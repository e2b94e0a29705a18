#pragma once
// A working segment is named by its label 1..N_w: in the label images, the
// plan file, the messages and the reports. Tables with one entry per segment
// start at 0. SegmentId and PerSegment<T> keep the two apart, so that the
// label-to-index shift is written once, here, and a table of segments cannot
// be indexed by a collector, an agent or a raw count by mistake.
#include <cassert>
#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace gather {

class SegmentId {
 public:
  constexpr SegmentId() = default;  // no segment (label 0)
  constexpr explicit SegmentId(int label) : label_(label) {}
  // The segment at position `index` of a per-segment table.
  static constexpr SegmentId at_index(std::size_t index) { return SegmentId(static_cast<int>(index) + 1); }

  constexpr int label() const { return label_; }       // 1..N_w; 0 = no segment
  constexpr bool valid() const { return label_ > 0; }  // names a segment
  // Names one of the segments 1..segments.
  constexpr bool within(int segments) const { return label_ >= 1 && label_ <= segments; }
  // Position in a per-segment table; only for a valid id.
  constexpr std::size_t index() const { return static_cast<std::size_t>(label_ - 1); }

  friend constexpr bool operator==(SegmentId a, SegmentId b) { return a.label_ == b.label_; }
  friend constexpr bool operator!=(SegmentId a, SegmentId b) { return a.label_ != b.label_; }
  friend constexpr bool operator<(SegmentId a, SegmentId b) { return a.label_ < b.label_; }

 private:
  int label_ = 0;
};

inline std::string to_string(SegmentId s) { return "segment " + std::to_string(s.label()); }
inline std::ostream& operator<<(std::ostream& out, SegmentId s) { return out << to_string(s); }

// One T per segment 1..N_w, indexed by SegmentId only.
template <class T>
class PerSegment {
 public:
  PerSegment() = default;
  explicit PerSegment(int segments, const T& fill = T{})
      : values_(segments > 0 ? static_cast<std::size_t>(segments) : 0, fill) {}
  // values[0] is segment 1's.
  explicit PerSegment(std::vector<T> values) : values_(std::move(values)) {}

  int segments() const { return static_cast<int>(values_.size()); }
  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  // The segment's entry; `s` must be in 1..segments().
  T& operator[](SegmentId s) {
    assert(s.within(segments()));
    return values_[s.index()];
  }
  const T& operator[](SegmentId s) const {
    assert(s.within(segments()));
    return values_[s.index()];
  }

  typename std::vector<T>::iterator begin() { return values_.begin(); }
  typename std::vector<T>::iterator end() { return values_.end(); }
  typename std::vector<T>::const_iterator begin() const { return values_.begin(); }
  typename std::vector<T>::const_iterator end() const { return values_.end(); }
  const std::vector<T>& values() const { return values_; }

  friend bool operator==(const PerSegment& a, const PerSegment& b) { return a.values_ == b.values_; }
  friend bool operator!=(const PerSegment& a, const PerSegment& b) { return a.values_ != b.values_; }

 private:
  std::vector<T> values_;
};

// The ids 1..n, for `for (SegmentId s : segment_ids(n))`.
class SegmentIds {
 public:
  class iterator {
   public:
    constexpr explicit iterator(int label) : label_(label) {}
    constexpr SegmentId operator*() const { return SegmentId(label_); }
    constexpr iterator& operator++() {
      ++label_;
      return *this;
    }
    friend constexpr bool operator!=(iterator a, iterator b) { return a.label_ != b.label_; }

   private:
    int label_;
  };
  constexpr explicit SegmentIds(int n) : n_(n > 0 ? n : 0) {}
  constexpr iterator begin() const { return iterator(1); }
  constexpr iterator end() const { return iterator(n_ + 1); }

 private:
  int n_;
};
constexpr SegmentIds segment_ids(int n) { return SegmentIds(n); }

}  // namespace gather
