#pragma once
// A radix heap of 64-bit keys (a time's float bits << 32 | a cell, as
// order_key makes them): the queue of a march or a search that takes keys
// in ascending order and queues keys above the last one taken, but for
// rounding, which may put one at or just below it: those are kept apart
// and taken first, smallest first. pop() always returns the smallest key
// queued, so the order is that of a binary heap of the same keys, at a
// fraction of the cost per key (no sifting: a key moves to a lower bucket
// at most 64 times). FrontGrowth::lower and the routes' A* use it.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gather {

class RadixQueue {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  void clear() {
    for (auto& b : buckets_) b.clear();
    last_ = 0, size_ = 0;
  }
  void push(uint64_t key) {
    buckets_[bucket(key, last_)].push_back(key);
    ++size_;
  }
  // The smallest key queued (the queue must not be empty).
  uint64_t pop() {
    if (buckets_[0].empty()) {
      // The first non-empty bucket: its smallest key is the next one, and
      // every key of it lands in a lower bucket relative to that key.
      std::size_t i = 1;
      while (buckets_[i].empty()) ++i;
      std::vector<uint64_t>& from = buckets_[i];
      last_ = *std::min_element(from.begin(), from.end());
      for (uint64_t k : from) buckets_[bucket(k, last_)].push_back(k);
      from.clear();
    }
    // Bucket 0 holds the last key taken again (equal ones are alike) and,
    // rarely, keys below it: the smallest goes first.
    std::vector<uint64_t>& zero = buckets_[0];
    if (zero.size() > 1) std::iter_swap(std::min_element(zero.begin(), zero.end()), zero.end() - 1);
    --size_;
    const uint64_t key = zero.back();
    zero.pop_back();
    return key;
  }

 private:
  // Bucket 0 holds the keys equal to the last one taken and those below it;
  // bucket i the keys whose highest bit that differs from it is bit i - 1.
  static std::size_t bucket(uint64_t key, uint64_t last) {
    return key <= last ? 0 : 64 - static_cast<std::size_t>(__builtin_clzll(key ^ last));
  }
  std::array<std::vector<uint64_t>, 65> buckets_;
  uint64_t last_ = 0;
  std::size_t size_ = 0;
};

}  // namespace gather
