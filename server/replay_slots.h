#pragma once
// How many replays may run at once (docs/security.md, "Bounded resources"). Each replay owns a
// simulation thread, a checkpointer and a renderer (about a core while it plays and tens of MB of
// checkpoints), so a viewer opening many would take the machine from the live sessions. A replay
// holds a slot for as long as its socket is open; a viewer over their share, or any viewer when
// all slots are taken, is closed with 1013 (try again later) and a reason that says which.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace incise::server {

class ReplaySlots {
 public:
  static constexpr int kDefaultPerUser = 3;
  // total 0: twice the machine's cores, at least four.
  explicit ReplaySlots(int per_user = kDefaultPerUser, int total = 0);

  // Releases its slot when destroyed (and hands the freed memory back to the system).
  class Slot {
   public:
    Slot(ReplaySlots& owner, std::int64_t user_id) : owner_(owner), user_id_(user_id) {}
    ~Slot();
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;

   private:
    ReplaySlots& owner_;
    std::int64_t user_id_;
  };

  // A slot for `user_id`, or nullptr with `why` saying which limit was reached.
  std::unique_ptr<Slot> take(std::int64_t user_id, std::string& why);

  int in_use() const;
  int per_user() const { return per_user_; }
  int total() const { return total_; }

 private:
  void release(std::int64_t user_id);

  int per_user_;
  int total_;
  mutable std::mutex mutex_;
  int in_use_ = 0;
  std::map<std::int64_t, int> per_user_in_use_;
};

}  // namespace incise::server
