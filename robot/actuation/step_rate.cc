#include "robot/actuation/step_rate.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>

#include "robot/actuation/actuation_config.h"

namespace robossis::actuation {

double MaxStepRateHz(const std::vector<StepEvent>& events, double window_s) {
  if (!(window_s > kStepRateTimeToleranceS)) {
    throw std::invalid_argument("step rate: the window must be longer than " +
                                std::to_string(kStepRateTimeToleranceS) + " s");
  }
  std::array<std::vector<double>, kNumMotors> times;
  for (const StepEvent& e : events) {
    if (e.motor >= 0 && e.motor < kNumMotors) times[e.motor].push_back(e.time_s);
  }
  std::size_t most = 0;
  for (const std::vector<double>& ts : times) {
    std::size_t first = 0;  // the oldest step inside (ts[i] - window_s, ts[i]]
    for (std::size_t i = 0; i < ts.size(); ++i) {
      while (ts[i] - ts[first] >= window_s - kStepRateTimeToleranceS) ++first;
      most = std::max(most, i - first + 1);
    }
  }
  return static_cast<double>(most) / window_s;
}

}  // namespace robossis::actuation
