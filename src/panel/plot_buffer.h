#pragma once
// The last seconds of a few signals for the panel's plots: a fixed-capacity ring of (time, values) samples. Pushing
// never allocates (the storage is reserved at construction); the oldest sample is overwritten when full.

#include <array>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace robossis::panel {

template <std::size_t N>
class PlotBuffer {
 public:
  using Values = std::array<float, N>;
  explicit PlotBuffer(std::size_t capacity) : time_s_(capacity), values_(capacity) {
    if (capacity == 0) throw std::invalid_argument("plot buffer: capacity must be positive");
  }

  void Push(double time_s, const Values& values) noexcept {
    time_s_[head_] = time_s;
    values_[head_] = values;
    head_ = (head_ + 1) % time_s_.size();
    if (size_ < time_s_.size()) ++size_;
  }

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return time_s_.size(); }
  // Sample i, oldest first (0 <= i < size()).
  double time_s(std::size_t i) const { return time_s_[Index(i)]; }
  const Values& values(std::size_t i) const { return values_[Index(i)]; }
  // Drops the samples older than `window_s` before the newest one.
  void TrimOlderThan(double window_s) noexcept {
    while (size_ > 1 && time_s(size_ - 1) - time_s(0) > window_s) --size_;
  }

 private:
  std::size_t Index(std::size_t i) const { return (head_ + time_s_.size() - size_ + i) % time_s_.size(); }
  std::vector<double> time_s_;
  std::vector<Values> values_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace robossis::panel
