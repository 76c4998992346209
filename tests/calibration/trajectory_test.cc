#include "calibration/trajectory.h"

#include <filesystem>
#include <fstream>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::calibration {
namespace {

using ::testing::HasSubstr;

TEST(TrajectoryTest, InterpolatesPositionLinearlyAndOrientationBySlerp) {
  PoseTrajectory traj;
  traj.Add(0.0, Eigen::Vector3d(0, 0, 0), Eigen::Quaterniond::Identity());
  traj.Add(2.0, Eigen::Vector3d(2, 4, 0), Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ())));
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
  ASSERT_TRUE(InterpolatePose(traj, 0.5, p, q));
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(0.5, 1.0, 0), 1e-15));
  EXPECT_NEAR(q.angularDistance(Eigen::Quaterniond::Identity()), 0.25, 1e-12);  // constant angular speed
  EXPECT_FALSE(InterpolatePose(traj, 2.0001, p, q));
  EXPECT_FALSE(InterpolatePose(traj, -0.1, p, q));
}

TEST(TrajectoryTest, KeepsQuaternionSignContinuous) {
  PoseTrajectory traj;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  traj.Add(0, Eigen::Vector3d::Zero(), q);
  traj.Add(1, Eigen::Vector3d::Zero(), Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()));
  EXPECT_GT(traj.q[0].dot(traj.q[1]), 0.99);
  Eigen::Vector3d p;
  Eigen::Quaterniond mid;
  ASSERT_TRUE(InterpolatePose(traj, 0.5, p, mid));
  EXPECT_LT(mid.angularDistance(q), 1e-12);  // not a detour through the other hemisphere
}

TEST(TrajectoryTest, ReadsProjectCsvInMmAndDegrees) {
  const std::string text =
      "# commanded by the GUI\n"
      "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,extra\n"
      "0.0,0,0,284,0,0,0,1\n"
      "0.5,10,-5,290,1,2,3,1\n";
  const PoseTrajectory traj = ParseTrajectoryCsv(text, "cmd.csv");
  ASSERT_EQ(traj.size(), 2u);
  EXPECT_TRUE(traj.p[1].isApprox(Eigen::Vector3d(0.010, -0.005, 0.290), 1e-15));
  EXPECT_TRUE(traj.q[1].toRotationMatrix().isApprox(RotationFromRpy(DegToRad(1.0) * Eigen::Vector3d(1, 2, 3)), 1e-12));
}

TEST(TrajectoryTest, ProjectCsvRoundTrips) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1, 1);
  PoseTrajectory traj;
  for (int i = 0; i < 50; ++i) {
    traj.Add(0.01 * i, Eigen::Vector3d(u(gen), u(gen), u(gen)) * 0.1,
             Eigen::Quaterniond(RotationFromVector(Eigen::Vector3d(u(gen), u(gen), u(gen)))));
  }
  const PoseTrajectory back = ParseTrajectoryCsv(FormatTrajectoryCsv(traj), "rt.csv");
  ASSERT_EQ(back.size(), traj.size());
  for (std::size_t i = 0; i < traj.size(); ++i) {
    EXPECT_NEAR(back.t_s[i], traj.t_s[i], 1e-9);
    EXPECT_LT((back.p[i] - traj.p[i]).norm(), 1e-9);
    EXPECT_LT(back.q[i].angularDistance(traj.q[i]), 1e-11);
  }
}

TEST(TrajectoryTest, TumRoundTripsAndIsDetected) {
  PoseTrajectory traj;
  traj.Add(10.0, Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())));
  traj.Add(10.1, Eigen::Vector3d(1, 2, 4), Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY())));
  const std::string tum = FormatTum(traj);
  EXPECT_THAT(tum, HasSubstr("10.000000000 1.000000000 2.000000000 3.000000000 0.000000000000 0.149438132474"));
  const PoseTrajectory back = ParseTum(tum, "t.tum");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_LT(back.q[1].angularDistance(traj.q[1]), 1e-11);
  const auto path = std::filesystem::temp_directory_path() / "robossis_trajectory_test.tum";
  { std::ofstream(path) << tum; }
  EXPECT_EQ(ReadReferenceTrajectory(path).size(), 2u);
  std::filesystem::remove(path);
}

TEST(TrajectoryTest, ClearErrors) {
  auto error = [](const std::string& text) {
    try {
      ParseTrajectoryCsv(text, "cmd.csv");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(error("x_m,y_m,z_m,qw,qx,qy,qz\n"), HasSubstr("no time column"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,0,abc,1,0,0,0\n"),
              HasSubstr("cmd.csv line 3: column 'z_m' is 'abc'"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n"), HasSubstr("does not increase"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,0\n"),
              HasSubstr("line 3: expected exactly 8 cells, one per header column, got 3"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0,7\n"),
              HasSubstr("line 3: expected exactly 8 cells, one per header column, got 9"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz,x_m\n"), HasSubstr("'x_m' appears twice (columns 2 and 9)"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n2e6,0,0,0,1,0,0,0\n"),
              HasSubstr("expected a span of at most"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m\n"), HasSubstr("no orientation columns"));
}

TEST(TrajectoryTest, HeaderlessCommaSeparatedFileIsNotGuessedAsTum) {
  try {
    ParseTum("0,0,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0\n", "ref.csv");
    FAIL() << "a headerless CSV was read as TUM";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("ref.csv line 1: commas in a TUM line"));
  }
}

TEST(TrajectoryTest, ReferenceReaderSkipsABomAndRefusesADirectory) {
  const auto path = std::filesystem::temp_directory_path() / "robossis_trajectory_bom.csv";
  { std::ofstream(path) << "\xEF\xBB\xBFt_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0\n"; }
  EXPECT_EQ(ReadReferenceTrajectory(path).size(), 2u);
  std::filesystem::remove(path);
  try {
    ReadReferenceTrajectory(std::filesystem::temp_directory_path());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("expected a regular file"));
  }
}

}  // namespace
}  // namespace robossis::calibration
