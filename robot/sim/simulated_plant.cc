#include "robot/sim/simulated_plant.h"

#include <cmath>
#include <stdexcept>

namespace robossis::sim {

namespace {

std::unique_ptr<RsrSimulation> NotNull(std::unique_ptr<RsrSimulation> simulation) {
  if (!simulation) throw std::invalid_argument("simulated plant: no simulation");
  return simulation;
}

}  // namespace

SimulatedPlant::SimulatedPlant(std::unique_ptr<RsrSimulation> simulation, double max_catch_up_s)
    : simulation_(NotNull(std::move(simulation))),
      max_catch_up_s_(max_catch_up_s),
      period_ns_(std::llround(simulation_->step_s() * 1e9)),
      enable_wanted_(simulation_->State().enabled),
      enabled_(simulation_->State().enabled),
      state_(simulation_->State()),
      plant_enabled_(simulation_->State().enabled) {
  if (!(max_catch_up_s > 0)) throw std::invalid_argument("simulated plant: max_catch_up_s must be > 0");
  latched_ = state_.fault;
  measured_.Publish(state_);
  measured_version_ = measured_.version();
}

bool SimulatedPlant::Enable() noexcept {
  if (latched_ != robot::FollowerFault::kNone) return false;  // robot::Follower: ResetFault first
  enabled_ = true;
  enable_wanted_.store(true, std::memory_order_release);
  return true;
}

void SimulatedPlant::Disable() noexcept {
  enabled_ = false;
  enable_wanted_.store(false, std::memory_order_release);
}

bool SimulatedPlant::ResetFault() noexcept {
  if (latched_ == robot::FollowerFault::kUnstable) return false;  // a diverged simulation does not come back
  latched_ = robot::FollowerFault::kNone;
  return true;
}

void SimulatedPlant::Command(const robot::RsrJointCommand& command) noexcept {
  if (enabled_) command_.Publish(command);
}

// The time is not used: the plant steps on its own clock, and the measurement carries the physics time it was made at.
void SimulatedPlant::Service(double) noexcept {
  robot::RsrFollowerState measured;
  if (!measured_.ReadNewer(measured, measured_version_)) return;
  state_ = measured;
  // Each measurement is a new step's condition: a fault it shows is latched until ResetFault().
  if (measured.faulted() && latched_ == robot::FollowerFault::kNone) latched_ = measured.fault;
}

robot::RsrFollowerState SimulatedPlant::State() const noexcept {
  robot::RsrFollowerState s = state_;
  s.fault = latched_;
  s.enabled = enabled_ && latched_ == robot::FollowerFault::kNone;
  s.homed = true;
  return s;
}

void SimulatedPlant::Tick(std::int64_t now_ns) noexcept {
  RsrSimulation& sim = *simulation_;
  const bool wanted = enable_wanted_.load(std::memory_order_acquire);
  if (wanted != plant_enabled_) {
    if (wanted) {
      // The follower side enables only with its latch clear, i.e. after its ResetFault(): acknowledged here too.
      sim.ResetFault();
      plant_enabled_ = sim.Enable();
    } else {
      sim.Disable();
      plant_enabled_ = false;
    }
  }
  robot::RsrJointCommand command;
  if (plant_enabled_ && command_.ReadNewer(command, command_version_)) sim.Command(command);
  const double now_s = 1e-9 * static_cast<double>(now_ns);
  const double behind_s = now_s - sim.time_s();
  if (behind_s > max_catch_up_s_) {
    const double skip_to_s = now_s - max_catch_up_s_;
    skipped_ns_.fetch_add(std::llround((skip_to_s - sim.time_s()) * 1e9), std::memory_order_relaxed);
    sim.SkipTo(skip_to_s);
  }
  const double before_s = sim.time_s();
  sim.Service(now_s);
  if (sim.time_s() != before_s) measured_.Publish(sim.State());
}

}  // namespace robossis::sim
