#pragma once
// A working segment is named by its label 1..N_w: in the label images, the
// plan file, the messages and the reports. Tables with one entry per segment
// start at 0. SegmentId and PerSegment<T> keep the two apart, so that the
// label-to-index shift is written once, here, and a table of segments cannot
// be indexed by a collector, an agent or a raw count by mistake.
#include <cstddef>
#include <ostream>
#include <string>

#include "gather_core/id_table.hpp"

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

// One T per segment 1..N_w, indexed by SegmentId only (entry 0: segment 1;
// count() is N_w).
template <class T>
using PerSegment = IdTable<SegmentId, T>;

// The ids 1..n, for `for (SegmentId s : segment_ids(n))`.
constexpr IdRange<SegmentId> segment_ids(int n) { return IdRange<SegmentId>(1, n + 1); }

}  // namespace gather
