#pragma once
// The follower-side passivity controller of the network form of time-domain passivity (Artigas, Ryu, Preusche and
// Hirzinger, IROS 2011): the leader's controller (feedback_passivity.h) bounds what the channel gives the hand by the
// energy that entered it at the follower; this one bounds what the channel gives the environment by the energy that
// entered it at the hand, E_out,F(k) <= E_in,L(k − T) / G, as received with the set-points (G the feedback gain: the
// hand's power is G times the follower's). Together the channel between the two ports is passive whatever the
// delay, jitter or loss: the robot cannot push harder into the environment than the hand has paid for.
//
// The port: the follower moves by the step dq (twist × dt, in F) against the environment's wrench W on it (in F);
// energy enters the network where W·dq > 0 (the environment pushes the ring along its motion), leaves it where
// W·dq < 0.
//
// Controller: admittance causality (the network's output at the follower is a motion), so the controller is a
// series element on the motion: the step toward the set-point is shortened, along its own direction, so that the
// energy it would give the environment at the last measured wrench fits the budget. The step is always taken from
// where the follower is to its newest set-point, so whatever a budget held back is made up as soon as energy allows
// (the drift compensation of Coelho, Ott et al.: the follower returns to the operator's position within the energy
// budget instead of accumulating the lag). The environment's wrench is known one sample late: the booked energy can
// exceed the budget by the wrench's change over one step (W(k) − W(k−1))·dq.
//
// Real time: every member is noexcept and allocation-free.

#include "src/core/pose.h"

namespace robossis::teleop {

struct FollowerPortEnergies {
  double in_j = 0;   // the environment gave the network (W·dq > 0)
  double out_j = 0;  // the network gave the environment (W·dq < 0)
};

class FollowerPassivity {
 public:
  // The share in [0, 1] of `step` the follower may take now: 1 while the energy it would give the environment at
  // `wrench_F` (the last measured) fits budget_j − E_out,F; budget_j is the energy the hand put into the network as
  // last received, divided by the feedback gain.
  double StepShare(const Vector6d& step, const Vector6d& wrench_F, double budget_j) const noexcept;
  // Books the step taken against the environment's wrench measured after it.
  void Book(const Vector6d& wrench_F, const Vector6d& step) noexcept;
  void Reset() noexcept { energies_ = {}; }
  const FollowerPortEnergies& energies() const noexcept { return energies_; }

 private:
  FollowerPortEnergies energies_;
};

}  // namespace robossis::teleop
