#pragma once
// A back end that passes every call to another one: the base of the tests' decorators, which change only what they
// are about (what the back end measures, or when) and leave the drives' behaviour to the inner back end.

#include "robot/follower.h"

namespace robossis::testing {

class ForwardingFollower : public robot::Follower {
 public:
  explicit ForwardingFollower(robot::Follower& inner) : inner_(inner) {}
  bool Enable() noexcept override { return inner_.Enable(); }
  void Disable() noexcept override { inner_.Disable(); }
  bool Home() noexcept override { return inner_.Home(); }
  bool MeasuresJoints() const noexcept override { return inner_.MeasuresJoints(); }
  bool ResetFault() noexcept override { return inner_.ResetFault(); }
  void Command(const robot::RsrJointCommand& command) noexcept override { inner_.Command(command); }
  void Service(double now_s) noexcept override { inner_.Service(now_s); }
  robot::RsrFollowerState State() const noexcept override { return inner_.State(); }

 protected:
  robot::Follower& inner_;
};

}  // namespace robossis::testing
