#include "gather_agent/roles/custody.hpp"

#include <limits>

namespace gather {
namespace agent {

Custody::Custody(std::size_t data_capacity, std::size_t notice_capacity)
    : entries_(data_capacity + notice_capacity), data_capacity_(data_capacity), notice_capacity_(notice_capacity) {}

bool Custody::holds(int32_t key) const {
  for (std::size_t i = 0; i < count_; ++i)
    if (entries_[i].item.key == key) return true;
  return false;
}

Custody::Put Custody::put(const DataItem& item) {
  if (holds(item.key)) return Put::kDuplicate;
  const bool data = item.kind == ItemKind::kMeasured;
  if (data ? data_full() : notices_full()) return Put::kFull;
  entries_[count_++] = Entry{item, -std::numeric_limits<double>::infinity()};
  if (data) ++data_;
  log(true, item);
  return Put::kStored;
}

void Custody::enable_log(std::size_t log_capacity) {
  logging_ = true;
  log_.reserve(log_capacity);
  log_.clear();
}

void Custody::log(bool put, const DataItem& item) {
  if (!logging_) return;
  if (log_.size() >= log_.capacity()) {
    log_overflow_ = true;
    return;
  }
  log_.push_back(Change{put, item});
}

std::size_t Custody::acked(const int32_t* keys, std::size_t n) {
  std::size_t removed = 0;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t i = 0; i < count_; ++i) {
      if (entries_[i].item.key != keys[k]) continue;
      if (entries_[i].item.kind == ItemKind::kMeasured) --data_;
      log(false, entries_[i].item);
      for (std::size_t j = i + 1; j < count_; ++j) entries_[j - 1] = entries_[j];
      --count_, ++removed;
      break;
    }
  return removed;
}

std::size_t Custody::due(double now, double resend_after, bool fresh_contact, DataBatch& batch) {
  batch.count = 0;
  for (std::size_t i = 0; i < count_ && batch.count < kMaxBatch; ++i) {
    Entry& e = entries_[i];
    if (!fresh_contact && e.sent_at > now - resend_after) continue;
    e.sent_at = now;
    batch.items[batch.count++] = e.item;
  }
  return batch.count;
}

}  // namespace agent
}  // namespace gather
