#include "server/replay_slots.h"

#include <malloc.h>

#include <algorithm>
#include <thread>

namespace incise::server {

ReplaySlots::ReplaySlots(int per_user, int total)
    : per_user_(per_user),
      total_(total > 0 ? total
                       : std::max(4, 2 * static_cast<int>(std::thread::hardware_concurrency()))) {}

ReplaySlots::Slot::~Slot() {
  owner_.release(user_id_);
}

std::unique_ptr<ReplaySlots::Slot> ReplaySlots::take(std::int64_t user_id, std::string& why) {
  std::lock_guard lock(mutex_);
  if (per_user_in_use_[user_id] >= per_user_) {
    why = "you have " + std::to_string(per_user_) +
          " replays open already; close one to open another";
    return nullptr;
  }
  if (in_use_ >= total_) {
    why = "the server is running its " + std::to_string(total_) +
          " replays at once; try again in a minute";
    return nullptr;
  }
  ++in_use_;
  ++per_user_in_use_[user_id];
  return std::make_unique<Slot>(*this, user_id);
}

void ReplaySlots::release(std::int64_t user_id) {
  {
    std::lock_guard lock(mutex_);
    --in_use_;
    if (--per_user_in_use_[user_id] <= 0) per_user_in_use_.erase(user_id);
  }
  // A replay's engine and checkpoints are tens of MB in many small blocks, freed by now; glibc
  // keeps freed memory in its arenas unless asked to return it.
  malloc_trim(0);
}

int ReplaySlots::in_use() const {
  std::lock_guard lock(mutex_);
  return in_use_;
}

}  // namespace incise::server
