// The simulated sigma.7 with a hand: device limits and the hand's impedance.

#include <gtest/gtest.h>

#include "haptics/device/device_sim.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

const robot::Sigma7Model& Sigma7() {
  static const robot::Sigma7Model model = robot::Sigma7Model::Default();
  return model;
}

Eigen::Isometry3d Centre() {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Sigma7().p_center_O();
  return X;
}

TEST(DeviceSim, HandSettlesOnItsTarget) {
  SimulatedSigma7 device(Sigma7(), testing::Config().device, testing::Config().hand);
  device.Reset(Centre());
  HandTarget target;
  target.X_OH = Centre();
  target.X_OH.translation() += Eigen::Vector3d(0.02, -0.01, 0.005);
  target.X_OH.linear() = RotationFromVector(Eigen::Vector3d(0.1, 0, 0.05));
  for (int k = 0; k < 5000; ++k) device.Step(1e-3, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), target);
  EXPECT_LT((device.pose().translation() - target.X_OH.translation()).norm(), 1e-5);
  EXPECT_LT(RotationAngleBetween(device.pose().linear(), target.X_OH.linear()), 1e-4);
}

TEST(DeviceSim, ForceIsClampedToTheDevicePeak) {
  // A 30 N command is displayed as 20 N (sigma.7 peak, robot/sigma7_model.h): the hand's static deflection says so
  // (a stiff grip keeps the deflection well inside the device workspace).
  HandParams hand = testing::Config().hand;
  hand.stiffness_n_per_m = 2000;
  SimulatedSigma7 device(Sigma7(), testing::Config().device, hand);
  device.Reset(Centre());
  HandTarget target;
  target.X_OH = Centre();
  DeviceStepResult step;
  for (int k = 0; k < 5000; ++k) step = device.Step(1e-3, Eigen::Vector3d(0, 0, 30), Eigen::Vector3d(0, 0, 1), target);
  EXPECT_TRUE(step.force_clamped);
  const double k_h = hand.stiffness_n_per_m;
  EXPECT_NEAR(device.pose().translation().z() - Centre().translation().z(), 20.0 / k_h, 1e-4);
  const double k_r = hand.rot_stiffness_nm_per_rad;
  EXPECT_NEAR(RotationAngleBetween(device.pose().linear(), Eigen::Matrix3d::Identity()), 0.4 / k_r, 1e-3);
}

TEST(DeviceSim, HandleStopsAtTheWorkspaceBoundary) {
  SimulatedSigma7 device(Sigma7(), testing::Config().device, testing::Config().hand);
  device.Reset(Centre());
  HandTarget target;
  target.X_OH = Centre();
  target.X_OH.translation() += Eigen::Vector3d(0.5, 0, 0);  // far beyond the delta's reach
  DeviceStepResult step;
  for (int k = 0; k < 3000; ++k) step = device.Step(1e-3, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), target);
  EXPECT_TRUE(step.at_mechanical_limit);
  EXPECT_TRUE(robot::IsInSigma7Workspace(Sigma7(), device.pose().translation(), device.pose().linear()));
}

}  // namespace
}  // namespace robossis::haptics
