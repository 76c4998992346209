// One hand-to-robot mapping: the set-points (eq. 10, transfer::IncrementalMapper) and the walls (HcToRsrMap, every
// renderer) go through the same frame map, rotation R_FO included. With a rotated R_FO a hand motion along d in O
// moves the set-point and the walls' pose along R_FO·d·scale in F, and a wall pushes the hand back in O (R_FOᵀ).
// Every check is chosen so that dropping the rotation on either side breaks it: the directions compared are far
// apart when R_FO is ignored (a guard asserts it).

#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "haptics/rendering/renderer_factory.h"
#include "haptics/scenarios/scenario.h"
#include "haptics/transfer/incremental_mapping.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "test_util.h"
#include "tests/support/alloc_counter.h"
#include "tests/support/scratch_dir.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Home;
using testing::Rsr;

struct Rotation {
  std::string name;
  Eigen::Matrix3d R_FO;
};

// 90° about z (HC x is RSR y) and a rotation about no principal axis.
std::vector<Rotation> Rotated() {
  return {{"yaw 90 deg", RotationFromRpy(Eigen::Vector3d(0, 0, DegToRad(90)))},
          {"roll 25, pitch -40, yaw 110 deg", RotationFromRpy(Eigen::Vector3d(DegToRad(25), DegToRad(-40),
                                                                              DegToRad(110)))}};
}

transfer::HcToRsrFrame Frame(const Eigen::Matrix3d& R_FO, double translation_scale) {
  transfer::HcToRsrFrame frame;
  frame.R_FO = R_FO;
  frame.translation_scale = translation_scale;
  return frame;
}

// The hand's pose at the clutch: the device centre region, handle level.
Eigen::Isometry3d HandAnchor() {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  return X;
}

double Cosine(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.dot(b) / (a.norm() * b.norm()); }

// The set-point increment eq. 10 makes of a slow hand move from the anchor by dp_O and a turn by phi_O.
Vector6d SetPointIncrement(const transfer::HcToRsrFrame& frame, const Eigen::Vector3d& dp_O,
                           const Eigen::Vector3d& phi_O) {
  transfer::MappingConfig mapping;
  static_cast<transfer::HcToRsrFrame&>(mapping) = frame;
  mapping.cap_headroom = 1.0;
  transfer::SpeedCaps caps;  // 1 s for the move, far below these caps: eq. 11 scales nothing
  caps.max_linear_speed_m_s = 1.0;
  caps.max_angular_speed_rad_s = 1.0;
  transfer::IncrementalMapper mapper(mapping, caps);
  transfer::MappingIncrement inc;
  transfer::HcSample s;
  s.p_OH = HandAnchor().translation();
  EXPECT_EQ(mapper.Push(s, inc), transfer::SampleVerdict::kAnchored);
  s.time_s = 1.0;
  s.p_OH += dp_O;
  s.R_OH = RotationFromVector(phi_O);
  EXPECT_EQ(mapper.Push(s, inc), transfer::SampleVerdict::kAccepted);
  EXPECT_DOUBLE_EQ(inc.scale_linear, 1.0);
  EXPECT_DOUBLE_EQ(inc.scale_angular, 1.0);
  return inc.delta_F;
}

// (a) The set-point and the walls' own RSR-side pose move along R_FO·d·scale; the handle's turn about a turns the
// ring about R_FO·a.
TEST(OneHandToRobotMapping, HandMotionMovesTheSetPointAndTheWallsPoseAlongRfoD) {
  const double scale = 2.0;
  const Eigen::Vector3d d_O = Eigen::Vector3d(0.8, -0.3, 0.2).normalized();
  const double step_m = 0.004;  // 8 mm at the ring: well inside the workspace from home
  const Eigen::Vector3d a_O = Eigen::Vector3d(-0.2, 0.9, 0.4).normalized();
  const double turn_rad = DegToRad(3);
  for (const Rotation& rotation : Rotated()) {
    SCOPED_TRACE(rotation.name);
    const transfer::HcToRsrFrame frame = Frame(rotation.R_FO, scale);
    const Eigen::Vector3d expected_F = scale * step_m * (rotation.R_FO * d_O);
    const Eigen::Vector3d expected_axis_F = rotation.R_FO * a_O;
    // Without R_FO the motion would go along d and about a: far from the expected directions.
    ASSERT_LT(Cosine(expected_F, d_O), 0.5);
    ASSERT_LT(Cosine(expected_axis_F, a_O), 0.5);

    // The set-point (eq. 10).
    const Vector6d delta_F = SetPointIncrement(frame, step_m * d_O, turn_rad * a_O);
    EXPECT_LT((delta_F.head<3>() - expected_F).norm(), 1e-12);
    EXPECT_LT((delta_F.tail<3>() - turn_rad * expected_axis_F).norm(), 1e-12);

    // The walls' map and the renderer's own pose (the proxy's god-object follows the hand in free space).
    HcToRsrMap map;
    map.X_OH_anchor = HandAnchor();
    map.X_FM_anchor = Home();
    map.frame = frame;
    Eigen::Isometry3d X_OH = HandAnchor();
    X_OH.translation() += step_m * d_O;
    X_OH.linear() = RotationFromVector(turn_rad * a_O);
    const Eigen::Isometry3d X_FM = map.ToRsr(X_OH);
    EXPECT_LT((X_FM.translation() - Home().translation() - expected_F).norm(), 1e-12);
    EXPECT_LT((RotationVector(X_FM.linear() * Home().linear().transpose()) - turn_rad * expected_axis_F).norm(),
              1e-12);
    // ToHc inverts it: the scenarios and the replay place the hand with it.
    EXPECT_TRUE(map.ToHc(X_FM).isApprox(X_OH, 1e-12));

    std::unique_ptr<HapticRenderer> r = MakeRenderer("proxy", Config(), Rsr(), map, 1000);
    r->Reset(HandAnchor());
    HapticInput in;
    in.X_OH = X_OH;
    HapticOutput out;
    for (int k = 0; k < 5; ++k) r->Tick(in, out);
    EXPECT_EQ(out.status, HapticStatus::kFree);
    ASSERT_NE(r->constrained_pose(), nullptr);
    EXPECT_LT((r->constrained_pose()->translation() - Home().translation() - expected_F).norm(), 1e-9);
    EXPECT_LT((r->constrained_pose()->translation() - X_FM.translation()).norm(), 1e-9);
  }
}

// (b) The ring pressed into the +x wall of F by a hand moving along d = R_FOᵀ·x̂ in O: the force on the hand, in O,
// opposes the hand's motion, for every method family (the clouds, the proxy, the device-safe presets). Without the
// rotation back (the wall's force, about −x̂, sent to the device as is) it would be about perpendicular to d
// (yaw 90°) or along it (the general rotation).
TEST(OneHandToRobotMapping, AWallTheRingPressesIntoPushesTheHandBackAgainstItsMotionInO) {
  const double scale = 2.0;
  const Eigen::Vector3d axis_F = Eigen::Vector3d::UnitX();
  const double reach = ReachAlongAxis(Rsr(), Home(), axis_F, false, 0.3);
  ASSERT_GT(reach, 0.05);
  const double speed_O = 0.05;  // m/s at the hand
  for (const Rotation& rotation : Rotated()) {
    const transfer::HcToRsrFrame frame = Frame(rotation.R_FO, scale);
    const Eigen::Vector3d d_O = frame.LinearToHc(axis_F).normalized();
    ASSERT_LT((d_O - rotation.R_FO.transpose() * axis_F).norm(), 1e-12);
    ASSERT_GT(Cosine(-axis_F, d_O), -0.3) << rotation.name;  // the unrotated wall force would not oppose d
    for (const char* method : {"pointcloud", "pointcloud-safe", "proxy", "proxy-safe"}) {
      SCOPED_TRACE(rotation.name + ", " + method);
      HcToRsrMap map;
      map.X_OH_anchor = HandAnchor();
      map.X_FM_anchor = Home();
      map.frame = frame;
      std::unique_ptr<HapticRenderer> r = MakeRenderer(method, Config(), Rsr(), map, 1000);
      r->Reset(HandAnchor());
      // From the anchor to 4 mm beyond the wall at the ring, at a steady hand speed, then held there.
      const double travel_O = (reach + 0.004) / scale;
      const int ticks = static_cast<int>(std::ceil(travel_O / (speed_O * 1e-3)));
      HapticInput in;
      HapticOutput out;
      for (int k = 0; k <= ticks + 20; ++k) {
        const bool moving = k < ticks;
        in.X_OH = HandAnchor();
        in.X_OH.translation() += std::min(1.0, static_cast<double>(k) / ticks) * travel_O * d_O;
        in.v_O = moving ? Eigen::Vector3d(speed_O * d_O) : Eigen::Vector3d::Zero();
        r->Tick(in, out);
      }
      // The pose the walls saw is beyond the +x wall of F, where the hand was sent.
      const Eigen::Vector3d pushed_F = map.ToRsr(in.X_OH).translation() - Home().translation();
      EXPECT_NEAR(pushed_F.dot(axis_F), reach + 0.004, 1e-9);
      EXPECT_LT((pushed_F - pushed_F.dot(axis_F) * axis_F).norm(), 1e-9);
      EXPECT_NE(out.status, HapticStatus::kFree);
      ASSERT_GT(out.f_O.norm(), 2.0);
      EXPECT_LT(Cosine(out.f_O, d_O), -0.9) << "f_O " << out.f_O.transpose() << ", d_O " << d_O.transpose();
    }
  }
}

// (b) The rotation back is exact: the same RSR-side state rendered through a rotated frame gives R_FOᵀ times the
// wrench of the identity frame (the hand's pose and velocity rotated so that the ring sees the same motion).
TEST(OneHandToRobotMapping, TheRenderedWrenchIsTheIdentityFramesRotatedByRfoTranspose) {
  const Eigen::Vector3d axis_F = Eigen::Vector3d::UnitX();
  const double reach = ReachAlongAxis(Rsr(), Home(), axis_F, false, 0.3);
  for (const Rotation& rotation : Rotated()) {
    for (const char* method : {"pointcloud", "proxy"}) {
      SCOPED_TRACE(rotation.name + ", " + method);
      HcToRsrMap identity;
      identity.X_OH_anchor = HandAnchor();
      identity.X_FM_anchor = Home();
      HcToRsrMap rotated = identity;
      rotated.frame = Frame(rotation.R_FO, 1.0);
      std::unique_ptr<HapticRenderer> r_identity = MakeRenderer(method, Config(), Rsr(), identity, 1000);
      std::unique_ptr<HapticRenderer> r_rotated = MakeRenderer(method, Config(), Rsr(), rotated, 1000);
      r_identity->Reset(HandAnchor());
      r_rotated->Reset(HandAnchor());
      HapticOutput out_identity, out_rotated;
      for (int k = 0; k <= 200; ++k) {
        // The ring moves along +x and turns about z in F, past the wall by the end.
        const double s = (reach + 0.003) * k / 200.0;
        const Eigen::Vector3d v_F(0.02, 0, 0), w_F(0, 0, 0.05);
        const Eigen::Matrix3d turn_F = RotationFromVector(Eigen::Vector3d(0, 0, DegToRad(2) * k / 200.0));
        HapticInput in_identity, in_rotated;
        in_identity.X_OH = HandAnchor();
        in_identity.X_OH.translation() += s * axis_F;
        in_identity.X_OH.linear() = turn_F;
        in_identity.v_O = v_F;
        in_identity.w_O = w_F;
        in_rotated.X_OH = HandAnchor();
        in_rotated.X_OH.translation() += rotation.R_FO.transpose() * (s * axis_F);
        in_rotated.X_OH.linear() = rotation.R_FO.transpose() * turn_F * rotation.R_FO;
        in_rotated.v_O = rotation.R_FO.transpose() * v_F;
        in_rotated.w_O = rotation.R_FO.transpose() * w_F;
        r_identity->Tick(in_identity, out_identity);
        r_rotated->Tick(in_rotated, out_rotated);
        ASSERT_EQ(out_identity.status, out_rotated.status) << "tick " << k;
        ASSERT_LT((out_rotated.f_O - rotation.R_FO.transpose() * out_identity.f_O).norm(), 1e-6) << "tick " << k;
        ASSERT_LT((out_rotated.tau_O - rotation.R_FO.transpose() * out_identity.tau_O).norm(), 1e-8) << "tick " << k;
      }
      EXPECT_GT(out_identity.f_O.norm(), 1.0);  // the wall was reached
    }
  }
}

// (c) The identity frame reproduces the earlier map: a pure offset in position, scaled, and the handle's relative
// rotation applied to the ring's anchor orientation.
TEST(OneHandToRobotMapping, TheIdentityFrameIsTheEarlierOffsetAndRelativeRotation) {
  HcToRsrMap map;
  map.X_OH_anchor = HandAnchor();
  map.X_OH_anchor.linear() = RotationFromRpy(Eigen::Vector3d(0.1, -0.2, 0.3));
  map.X_FM_anchor = Home();
  map.X_FM_anchor.linear() = RotationFromRpy(Eigen::Vector3d(-0.05, 0.04, 0.2));
  map.frame.translation_scale = 1.5;
  Eigen::Isometry3d X_OH = map.X_OH_anchor;
  X_OH.translation() += Eigen::Vector3d(0.01, 0.02, -0.015);
  X_OH.linear() = RotationFromRpy(Eigen::Vector3d(0.3, 0.1, -0.2));
  const Eigen::Isometry3d X_FM = map.ToRsr(X_OH);
  const Eigen::Vector3d p_earlier =
      map.X_FM_anchor.translation() + 1.5 * (X_OH.translation() - map.X_OH_anchor.translation());
  const Eigen::Matrix3d R_earlier = X_OH.linear() * map.X_OH_anchor.linear().transpose() * map.X_FM_anchor.linear();
  EXPECT_LT((X_FM.translation() - p_earlier).norm(), 1e-15);
  EXPECT_LT((X_FM.linear() - R_earlier).norm(), 1e-14);
  EXPECT_TRUE(map.ToHc(X_FM).isApprox(X_OH, 1e-12));
  // The set-point increment is the hand's, scaled.
  const Eigen::Vector3d dp_O(0.002, -0.001, 0.0005);
  const Vector6d delta_F = SetPointIncrement(map.frame, dp_O, Eigen::Vector3d(0, 0, 0.01));
  EXPECT_LT((delta_F.head<3>() - 1.5 * dp_O).norm(), 1e-15);
  EXPECT_LT((delta_F.tail<3>() - Eigen::Vector3d(0, 0, 0.01)).norm(), 1e-15);
}

// A frame that is not a proper rotation, or a scale that is not positive, is refused when the renderer is built.
TEST(OneHandToRobotMapping, TheRendererRefusesAFrameThatIsNotAProperRotation) {
  HcToRsrMap map;
  map.frame.R_FO = 2.0 * Eigen::Matrix3d::Identity();
  EXPECT_THROW(MakeRenderer("proxy", Config(), Rsr(), map, 1000), std::invalid_argument);
  map.frame.R_FO = -Eigen::Matrix3d::Identity();  // a reflection
  EXPECT_THROW(MakeRenderer("proxy", Config(), Rsr(), map, 1000), std::invalid_argument);
  map.frame.R_FO = Eigen::Matrix3d::Identity();
  map.frame.rotation_scale = 0;
  EXPECT_THROW(MakeRenderer("proxy", Config(), Rsr(), map, 1000), std::invalid_argument);
}

// The tick stays allocation-free through a rotated frame, with a rotation scale other than 1 too (the exponential
// map instead of the conjugation).
TEST(OneHandToRobotMapping, ATickThroughARotatedFrameAllocatesNothing) {
  HcToRsrMap map;
  map.X_FM_anchor = Home();
  map.frame = Frame(Rotated().back().R_FO, 2.0);
  map.frame.rotation_scale = 0.5;
  for (const char* method : {"pointcloud", "proxy", "proxy-pc"}) {
    std::unique_ptr<HapticRenderer> r = MakeRenderer(method, Config(), Rsr(), map, 1000);
    r->Reset(Eigen::Isometry3d::Identity());
    HapticInput in;
    HapticOutput out;
    robossis::testing::AllocationCounter counter;
    for (int k = 0; k < 300; ++k) {
      in.X_OH.translation() = map.frame.LinearToHc(Eigen::Vector3d(0.0006 * k, 0, 0));
      in.X_OH.linear() = RotationFromVector(Eigen::Vector3d(0.001 * k, 0, 0.002 * k));
      in.v_O = map.frame.LinearToHc(Eigen::Vector3d(0.6, 0, 0));
      r->Tick(in, out);
    }
    EXPECT_EQ(counter.count(), 0u) << method;
    EXPECT_NE(out.status, HapticStatus::kFree) << method;  // the walls were reached
  }
}

// haptics.yaml has no mapping of its own: its old `mapping.scale` duplicated transfer.yaml's translation_scale (and
// had no rotation). A config that still carries it is refused, naming the key's new place.
TEST(OneHandToRobotMapping, AMappingSectionInHapticsYamlIsRefusedNamingTransferYaml) {
  std::ifstream in(DefaultDataDir() / "config" / "haptics.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(text.find("\nmapping:"), std::string::npos);
  robossis::testing::ScratchDir dir("robossis_haptics_mapping_test");
  std::filesystem::create_directories(dir.path());
  std::ofstream(dir.path() / "haptics.yaml") << text << "mapping:\n  scale: 1\n";
  try {
    HapticsConfig::FromYaml(dir.path() / "haptics.yaml");
    FAIL() << "haptics.yaml's mapping section was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'mapping': this section moved to transfer.yaml 'mapping'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace robossis::haptics
