#include "devices/agent/histogram.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace incise::devices::agent {

Histogram::Histogram(uint64_t bin_width, std::size_t bin_count)
    : width_(bin_width), bins_(bin_count + 1) {
  if (bin_width == 0 || bin_count == 0) {
    throw std::invalid_argument("Histogram needs a bin width and a bin count >= 1");
  }
}

void Histogram::add(uint64_t value) {
  const uint64_t bin = std::min<uint64_t>(value / width_, bins_.size() - 1);
  bump(bins_[bin]);
  if (value > max_.load(std::memory_order_relaxed)) {
    max_.store(value, std::memory_order_relaxed);
  }
}

uint64_t Histogram::count() const {
  uint64_t total = 0;
  for (const auto& bin : bins_)
    total += bin.load(std::memory_order_relaxed);
  return total;
}

uint64_t Histogram::percentile(double p) const {
  // With a concurrent writer the bins may have grown since count(): the rank is still reached,
  // at worst one sample late, or falls to the overflow bin's max().
  const uint64_t total = count();
  if (total == 0) return 0;
  const auto rank = std::max<uint64_t>(
      1, static_cast<uint64_t>(std::ceil(std::clamp(p, 0.0, 100.0) / 100.0 * total)));
  uint64_t seen = 0;
  for (std::size_t i = 0; i + 1 < bins_.size(); ++i) {
    seen += bins_[i].load(std::memory_order_relaxed);
    if (seen >= rank) return i * width_;
  }
  return max();
}

}  // namespace incise::devices::agent
