#pragma once
// Custody of the items an agent carries towards the OC (measured data and
// notices of expired, dropped or skipped goals): an item changes hands only
// against an ack. The holder keeps it until acked and sends it again at the
// next contact (or after `resend_after` seconds in contact without an ack);
// a receiver keeps one copy per key. Fixed capacity, allocated once: a full
// buffer refuses (the sender keeps its copy), nothing is overwritten.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_agent/messages.hpp"

namespace gather {
namespace agent {

class Custody {
 public:
  // Room for `data_capacity` measured items and `notice_capacity` notices.
  Custody(std::size_t data_capacity, std::size_t notice_capacity);

  enum class Put { kStored, kDuplicate, kFull };
  // Takes custody of `item` (a copy already held: kDuplicate, unchanged).
  Put put(const DataItem& item);
  bool holds(int32_t key) const;
  // Removes the acked keys; returns how many were held.
  std::size_t acked(const int32_t* keys, std::size_t n);

  // Fills `batch` with the items due at `now` [s]: never sent, sent before
  // now - resend_after, or every one when `fresh_contact` (a new contact
  // began); oldest first, at most kMaxBatch; marks them sent at `now`.
  std::size_t due(double now, double resend_after, bool fresh_contact, DataBatch& batch);

  std::size_t size() const { return count_; }
  std::size_t data() const { return data_; }  // measured items held
  std::size_t notices() const { return count_ - data_; }
  bool data_full() const { return data_ >= data_capacity_; }
  bool notices_full() const { return count_ - data_ >= notice_capacity_; }
  const DataItem& item(std::size_t i) const { return entries_[i].item; }

  // Change log, for a journal (runner/journal): once enabled, every item
  // stored and every key acked away is logged until clear_changes(); at
  // most log_capacity changes (more: overflowed(), the journal then writes
  // the whole custody again). Fixed capacity, allocated here.
  struct Change {
    bool put = false;  // stored (item), else acked away (item.key)
    DataItem item;
  };
  void enable_log(std::size_t log_capacity);
  const std::vector<Change>& changes() const { return log_; }
  bool overflowed() const { return log_overflow_; }
  void clear_changes() { log_.clear(), log_overflow_ = false; }

 private:
  struct Entry {
    DataItem item;
    double sent_at;
  };
  std::vector<Entry> entries_;  // [0, count_) in arrival order
  std::size_t count_ = 0, data_ = 0;
  std::size_t data_capacity_, notice_capacity_;
  bool logging_ = false, log_overflow_ = false;
  std::vector<Change> log_;
  void log(bool put, const DataItem& item);
};

}  // namespace agent
}  // namespace gather
