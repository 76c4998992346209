// The one HC -> RSR frame map (transfer.yaml `mapping`): directions into F by R_FO and the nominal scales, back into O
// by R_FOᵀ, rotations by conjugation; eq. 10's increments through it; transfer.yaml's rotation reaching it.

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "haptics/transfer/hc_to_rsr_frame.h"
#include "haptics/transfer/incremental_mapping.h"
#include "haptics/transfer/transfer_config.h"
#include "src/core/config.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "tests/support/scratch_dir.h"

namespace robossis::transfer {
namespace {

Eigen::Matrix3d General() { return RotationFromRpy(Eigen::Vector3d(DegToRad(25), DegToRad(-40), DegToRad(110))); }

TEST(HcToRsrFrame, MapsDirectionsIntoFAndWrenchesBackIntoO) {
  HcToRsrFrame frame;
  frame.R_FO = General();
  frame.translation_scale = 2.5;
  frame.rotation_scale = 0.5;
  const Eigen::Vector3d d(0.3, -0.7, 0.2);
  EXPECT_LT((frame.LinearToRsr(d) - 2.5 * (General() * d)).norm(), 1e-15);
  EXPECT_LT((frame.AngularToRsr(d) - 0.5 * (General() * d)).norm(), 1e-15);
  EXPECT_LT((frame.LinearToHc(frame.LinearToRsr(d)) - d).norm(), 1e-15);
  EXPECT_LT((frame.AngularToHc(frame.AngularToRsr(d)) - d).norm(), 1e-15);
  EXPECT_LT((frame.WrenchToHc(d) - General().transpose() * d).norm(), 1e-15);
  EXPECT_LT((frame.WrenchToRsr(frame.WrenchToHc(d)) - d).norm(), 1e-15);
  // A turn about a in O is a turn about R_FO·a in F, scaled.
  const Eigen::Matrix3d dR_O = RotationFromVector(d);
  EXPECT_LT((RotationVector(frame.RotationToRsr(dR_O)) - 0.5 * (General() * d)).norm(), 1e-12);
  EXPECT_LT((frame.RotationToHc(frame.RotationToRsr(dR_O)) - dR_O).norm(), 1e-12);
  // At rotation scale 1 the conjugation, the same turn.
  frame.rotation_scale = 1;
  EXPECT_LT((frame.RotationToRsr(dR_O) - General() * dR_O * General().transpose()).norm(), 1e-15);
  EXPECT_LT((RotationVector(frame.RotationToRsr(dR_O)) - General() * d).norm(), 1e-12);
}

// eq. 10 with a general rotation and a scale: a hand step along d moves the set-point along R_FO·d·scale, which is
// far from d (so an ignored R_FO fails); the identity frame passes the hand's step, scaled.
TEST(HcToRsrFrame, IncrementsFollowRfoTimesTheHandsDirection) {
  const Eigen::Vector3d d_O = Eigen::Vector3d(0.8, -0.3, 0.2).normalized();
  for (const bool rotated : {true, false}) {
    MappingConfig m;
    m.cap_headroom = 1.0;
    m.translation_scale = 2.0;
    if (rotated) m.R_FO = General();
    ASSERT_LT(d_O.dot(General() * d_O), 0.5);
    IncrementalMapper mapper(m, SpeedCaps{});
    MappingIncrement inc;
    HcSample s;
    mapper.Push(s, inc);
    s.time_s = 0.001;
    s.p_OH = 3e-6 * d_O;  // 3 mm/s at the hand, 6 mm/s at the ring: below the 10 mm/s cap
    ASSERT_EQ(mapper.Push(s, inc), SampleVerdict::kAccepted);
    const Eigen::Vector3d expected = 2.0 * 3e-6 * (rotated ? Eigen::Vector3d(General() * d_O) : d_O);
    EXPECT_LT((inc.delta_F.head<3>() - expected).norm(), 1e-18) << (rotated ? "rotated" : "identity");
  }
}

// transfer.yaml's rsr_from_hc_rpy_deg is the frame's R_FO, and a reflection or a zero scale is refused by key.
TEST(HcToRsrFrame, TransferYamlOwnsTheFrame) {
  const std::filesystem::path shipped = DefaultDataDir() / "config" / "transfer.yaml";
  std::ifstream in(shipped);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "rsr_from_hc_rpy_deg: [0, 0, 0]";
  ASSERT_NE(text.find(key), std::string::npos);
  robossis::testing::ScratchDir dir("robossis_transfer_frame_test");
  std::filesystem::create_directories(dir.path());
  const auto write = [&](const std::string& replacement) {
    std::string t = text;
    t.replace(t.find(key), key.size(), replacement);
    std::ofstream(dir.path() / "transfer.yaml") << t;
    return dir.path() / "transfer.yaml";
  };
  const TransferConfig c = TransferConfig::FromYaml(write("rsr_from_hc_rpy_deg: [25, -40, 110]"));
  EXPECT_LT((c.mapping.frame().R_FO - General()).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(c.mapping.frame().translation_scale, c.mapping.translation_scale);
  TransferConfig bad = c;
  bad.mapping.R_FO = -Eigen::Matrix3d::Identity();
  try {
    bad.Validate();
    FAIL() << "a reflection was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("transfer config: 'mapping.rsr_from_hc_rpy_deg': expected a proper rotation"),
              std::string::npos)
        << e.what();
  }
  bad = c;
  bad.mapping.rotation_scale = 0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace robossis::transfer
