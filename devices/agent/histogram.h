#pragma once
// A fixed-bin histogram of non-negative integers (tick periods, round trips in us): constant
// memory, no allocation after construction, O(1) to add to, and percentiles to within one bin.
//
// One thread adds; any thread may read at any time. Bins are atomics written with relaxed
// load + store (no locked instruction on the 1 kHz path), so a reader sees a consistent-enough
// snapshot for a log line (a value added during the read may be missing) and never a data race.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace incise::devices::agent {

class Histogram {
 public:
  // bin_count bins of bin_width from 0 (bin i holds [i * width, (i + 1) * width)), plus one
  // overflow bin for larger values. bin_width >= 1, bin_count >= 1.
  Histogram(uint64_t bin_width, std::size_t bin_count);

  // Writer only.
  void add(uint64_t value);

  uint64_t count() const;
  uint64_t max() const { return max_.load(std::memory_order_relaxed); }

  // The nearest-rank p-th percentile, p in (0, 100]: the ceil(p / 100 * count)-th smallest value,
  // rounded down to its bin's lower edge (so exact when bin_width is 1); a value in the overflow
  // bin reads as max(). 0 when empty.
  uint64_t percentile(double p) const;

  uint64_t bin_width() const { return width_; }

 private:
  static void bump(std::atomic<uint64_t>& counter, uint64_t by = 1) {
    counter.store(counter.load(std::memory_order_relaxed) + by, std::memory_order_relaxed);
  }

  uint64_t width_;
  std::vector<std::atomic<uint64_t>> bins_;  // the last one is the overflow bin
  std::atomic<uint64_t> max_{0};
};

}  // namespace incise::devices::agent
