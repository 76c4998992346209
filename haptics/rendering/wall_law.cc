#include "haptics/rendering/wall_law.h"

#include <stdexcept>
#include <string>

namespace robossis::haptics {

WeightedMovingAverage::WeightedMovingAverage(int window) : window_(window) {
  if (window < 1 || window > kMaxWindow) {
    throw std::invalid_argument("moving_average_window: expected an integer in [1, " + std::to_string(kMaxWindow) +
                                "], got " + std::to_string(window));
  }
}

double WeightedMovingAverage::Weight(int age) const noexcept {
  if (age < 0 || age >= window_) return 0.0;
  return static_cast<double>(window_ - age) / (0.5 * window_ * (window_ + 1));
}

Vector6d WeightedMovingAverage::Filter(const Vector6d& sample) noexcept {
  samples_[next_] = sample;
  next_ = (next_ + 1) % window_;
  if (count_ < window_) ++count_;
  // The newest sample (age 0) gets weight count_, the oldest weight 1.
  Vector6d sum = Vector6d::Zero();
  double weight_sum = 0;
  for (int age = 0; age < count_; ++age) {
    const int index = (next_ - 1 - age + 2 * window_) % window_;
    const double w = count_ - age;
    sum += w * samples_[index];
    weight_sum += w;
  }
  return sum / weight_sum;
}

}  // namespace robossis::haptics
