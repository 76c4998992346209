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


TEST(DeviceSim, NoWorkIsCountedOnAHandleHeldAtAStop) {
  // The displayed force presses the handle against the delta workspace boundary (the hand pulls the same way): the
  // handle does not move, so the device does no work on the hand. Before the fix the step counted F·v·h with the
  // velocity computed before the stop zeroed it — phantom energy that render-compare reported as "generated" by the
  // wall (0.4 J of pointcloud-safe's 0.74 J on push-edges, haptics/README.md).
  SimulatedSigma7 device(Sigma7(), testing::Config().device, testing::Config().hand);
  device.Reset(Centre());
  HandTarget target;
  target.X_OH = Centre();
  target.X_OH.translation() += Eigen::Vector3d(0.5, 0, 0);  // far beyond the delta's reach
  const Eigen::Vector3d push(10, 0, 0);                     // the wall pushes the same way
  DeviceStepResult step;
  for (int k = 0; k < 3000; ++k) step = device.Step(1e-3, push, Eigen::Vector3d::Zero(), target);
  ASSERT_TRUE(step.at_mechanical_limit);
  const Eigen::Vector3d p_stop = device.pose().translation();
  double energy = 0;
  for (int k = 0; k < 100; ++k) energy += device.Step(1e-3, push, Eigen::Vector3d::Zero(), target).energy_into_hand_j;
  // The handle may slide along the boundary surface; the work counted must equal F·Δp of the motion that happened.
  EXPECT_NEAR(energy, push.dot(device.pose().translation() - p_stop), 1e-9);
}

TEST(DeviceSim, NoWorkIsCountedOnAWristHeldAtItsStop) {
  SimulatedSigma7 device(Sigma7(), testing::Config().device, testing::Config().hand);
  device.Reset(Centre());
  HandTarget target;
  target.X_OH = Centre();
  target.X_OH.linear() = RotationFromVector(Eigen::Vector3d(0, 0, 3.0));  // beyond the wrist's yaw range
  const Eigen::Vector3d twist(0, 0, 0.2);                                 // the wall turns the same way
  DeviceStepResult step;
  for (int k = 0; k < 3000; ++k) step = device.Step(1e-3, Eigen::Vector3d::Zero(), twist, target);
  ASSERT_TRUE(step.at_mechanical_limit);
  const Eigen::Matrix3d R_stop = device.pose().linear();
  double energy = 0;
  for (int k = 0; k < 100; ++k) energy += device.Step(1e-3, Eigen::Vector3d::Zero(), twist, target).energy_into_hand_j;
  EXPECT_NEAR(energy, twist.dot(RotationVector(device.pose().linear() * R_stop.transpose())), 1e-6);
}

}  // namespace
}  // namespace robossis::haptics
