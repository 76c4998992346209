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
              HasSubstr("cmd.csv line 3, column 4 (z_m): got 'abc'; expected a finite number"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n"),
              HasSubstr("line 3, column 1 (t_s): got '0'; expected a time greater than 0"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,0\n"),
              HasSubstr("line 3: 3 cells; expected exactly 8, one per header column"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0,7\n"),
              HasSubstr("line 3: 9 cells; expected exactly 8, one per header column"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz,x_m\n"), HasSubstr("'x_m' appears twice (columns 2 and 9)"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n2e6,0,0,0,1,0,0,0\n"),
              HasSubstr("expected a span of at most"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m\n"), HasSubstr("no orientation columns"));
}

// The project CSV goes through the one strict CSV reader: the hostile cases of a hand-edited or spreadsheet file.
TEST(TrajectoryTest, ProjectCsvHostileCasesAreErrorsOrReadExactly) {
  auto error = [](const std::string& text) {
    try {
      ParseTrajectoryCsv(text, "ref.csv");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string header = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  const std::string rows = "0,0,0,0.1,1,0,0,0\n0.1,0.2,0,0.1,1,0,0,0\n";
  // Quoted header names and a byte-order mark read exactly as the plain file (they were "no time column").
  const PoseTrajectory plain = ParseTrajectoryCsv(header + rows, "ref.csv");
  const PoseTrajectory quoted =
      ParseTrajectoryCsv("\"t_s\",\"x_m\",\"y_m\",\"z_m\",\"qw\",\"qx\",\"qy\",\"qz\"\n" + rows, "ref.csv");
  const PoseTrajectory bom = ParseTrajectoryCsv("\xEF\xBB\xBF" + header + rows, "ref.csv");
  ASSERT_EQ(plain.size(), 2u);
  ASSERT_EQ(quoted.size(), 2u);
  ASSERT_EQ(bom.size(), 2u);
  EXPECT_EQ(quoted.p[1], plain.p[1]);
  EXPECT_EQ(bom.p[1], plain.p[1]);
  // One extra cell, a name twice (also an ignored one), times going back, a NaN or an unterminated quote.
  EXPECT_THAT(error(header + rows + "0.2,0,0,0,1,0,0,0,5\n"), HasSubstr("ref.csv line 4: 9 cells; expected exactly 8"));
  EXPECT_THAT(error("t_s,x_m,y_m,z_m,qw,qx,qy,qz,note,note\n"), HasSubstr("'note' appears twice (columns 9 and 10)"));
  EXPECT_THAT(error(header + rows + "0.05,0,0,0,1,0,0,0\n"),
              HasSubstr("ref.csv line 4, column 1 (t_s): got '0.05'; expected a time greater than 0.1"));
  EXPECT_THAT(error(header + "0,0,0,nan,1,0,0,0\n0.1,0,0,0,1,0,0,0\n"),
              HasSubstr("line 2, column 4 (z_m): got 'nan'; expected a finite number"));
  EXPECT_THAT(error(header + "0,\"0,0,0,1,0,0,0\n"), HasSubstr("ref.csv line 2, field 2: unterminated quote"));
  EXPECT_THAT(error(header + "1e11,0,0,0,1,0,0,0\n"), HasSubstr("expected a time in [-10000000000, 10000000000]"));
  EXPECT_THAT(error("# only a comment\n\n"), HasSubstr("ref.csv: empty"));
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
