// The Motive CSV reader against real exports (tests/calibration/data/README.md) and against every flavour the
// synthetic tracker writes.

#include "calibration/motive_csv.h"

#include <cmath>
#include <fstream>
#include <random>
#include <regex>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "calibration/mocap_track.h"
#include "src/core/files.h"
#include "tests/calibration/test_support.h"

namespace robossis::calibration {
namespace {

using ::testing::HasSubstr;
using testing::DataFile;

std::string Error(const std::string& text) {
  try {
    MotiveReader reader(text, "take.csv");
    MotiveRow row;
    while (reader.ReadFrame(row)) {
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Real export 1 (format 1.21, cmuphyscomp/hmv-s16): counts and the first row's values (read off the file).
TEST(MotiveCsvTest, ReadsFormat121Export) {
  const MotiveTakeSummary s = InspectMotiveTake(DataFile("cmuphyscomp_hmv-s16_sample_optitrack_take.csv"));
  EXPECT_EQ(s.header.format_version, "1.21");
  EXPECT_DOUBLE_EQ(s.header.export_rate_hz, 120.0);
  EXPECT_EQ(s.frames, 250);
  ASSERT_EQ(s.rigid_bodies.size(), 1u);
  EXPECT_EQ(s.rigid_bodies[0].name, "Rigid Body 1");
  EXPECT_EQ(s.rigid_bodies[0].gaps.frames_present, 250);
  EXPECT_EQ(s.rigid_bodies[0].gaps.gaps, 0);
  EXPECT_EQ(s.rigid_bodies[0].rigid_body_markers, 3);
  EXPECT_EQ(s.markers, 9);  // Unlabeled:105..111 (6) + Rigid Body 1:Marker1..3
}

TEST(MotiveCsvTest, ReadsFirstPoseOfFormat121ExportInSi) {
  MotiveReader reader(DataFile("cmuphyscomp_hmv-s16_sample_optitrack_take.csv"));
  MotiveRow row;
  ASSERT_TRUE(reader.ReadFrame(row));
  const auto X = reader.RigidBodyPose(row, 0);
  ASSERT_TRUE(X.has_value());
  // Row "0,0.000000,0.000035,0.000016,-0.000030,-1.000000,0.060002,0.019150,0.076611,...": metres already.
  EXPECT_NEAR(X->translation().x(), 0.060002, 1e-12);
  EXPECT_NEAR(X->translation().z(), 0.076611, 1e-12);
  EXPECT_TRUE(X->linear().isApprox(Eigen::Matrix3d::Identity(), 1e-3));  // W = -1: identity rotation
  EXPECT_EQ(row.frame, 0);
  // Error Per Marker (1.21's quality column) is read.
  EXPECT_NEAR(row.Length(reader.layout().rigid_bodies[0].mean_marker_error), 0.000004, 1e-12);
}

// Real export 2 (format 1.23, timeanddoctor/parse_optitrack_csv): the rigid body is blank at frame 4.
TEST(MotiveCsvTest, ReadsFormat123ExportWithDropout) {
  const MotiveTakeSummary s = InspectMotiveTake(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  EXPECT_EQ(s.header.format_version, "1.23");
  EXPECT_EQ(s.frames, 499);
  ASSERT_EQ(s.rigid_bodies.size(), 1u);
  EXPECT_EQ(s.rigid_bodies[0].name, "ernesto_body");
  EXPECT_EQ(s.rigid_bodies[0].gaps.frames_present, 498);
  EXPECT_EQ(s.rigid_bodies[0].gaps.gaps, 1);
  EXPECT_EQ(s.rigid_bodies[0].gaps.longest_gap_frames, 1);
  EXPECT_EQ(s.rigid_bodies[0].rigid_body_markers, 4);
  EXPECT_EQ(s.markers, 4);
}

TEST(MotiveCsvTest, EmptyCellsAreMissingNotZero) {
  const RigidBodyTrack track = ReadRigidBodyTrack(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"), "ernesto_body");
  ASSERT_EQ(track.size(), 499u);
  EXPECT_EQ(track.present[4], 0);
  EXPECT_EQ(track.present[3], 1);
  EXPECT_TRUE(std::isnan(track.mean_marker_error_m[4]));
  EXPECT_NEAR(track.p_TB[5].x(), 3.717959, 1e-12);
  EXPECT_NEAR(track.t_s[6], 6.0 / 120.0, 1e-15);
}

// Real export 3 (ha5dzs/optitrack-motive-file-converter): no assets at all.
TEST(MotiveCsvTest, RejectsTakeWithoutAssets) {
  try {
    MotiveReader reader(DataFile("ha5dzs_optitrack-motive-file-converter_test_default.csv"));
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no assets"));
    EXPECT_THAT(e.what(), HasSubstr("test_default.csv"));
  }
}

TEST(MotiveCsvTest, RejectsLegacyFormat11) {
  EXPECT_THAT(Error("Format Version,1.1,Take Name,old\nframe,0\n"), HasSubstr("legacy format 1.1"));
  EXPECT_THAT(Error("comment,Motive 1.0 export\ninfo,framecount,10\n"), HasSubstr("legacy"));
}

TEST(MotiveCsvTest, RejectsGarbage) {
  EXPECT_THAT(Error(""), HasSubstr("empty"));
  EXPECT_THAT(Error("hello,world\n1,2,3\n"), HasSubstr("expected 'Format Version"));
  EXPECT_THAT(Error("\x01\x02\x03\xff\xfe"), HasSubstr("take.csv line 1"));
}

TEST(MotiveCsvTest, RejectsTruncatedHeader) {
  const std::string text = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  EXPECT_THAT(Error(text.substr(0, text.find("Rotation,Rotation"))), HasSubstr("ends inside the header"));
}

TEST(MotiveCsvTest, RejectsTruncatedRowMidNumber) {
  const std::string text = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  // Cut inside a row's cell "-0.649345" → "-0.6-" is not a number... cut at a '.' leaving "3."? Use a garbled tail.
  const std::size_t row = text.find("\n3,0.025000");
  const std::string cut = text.substr(0, row + 40) + "x\r\n";
  EXPECT_THAT(Error(cut), HasSubstr("truncated"));
}

TEST(MotiveCsvTest, RejectsFileCutInsideTheLastRow) {
  const std::string text = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  const std::size_t row = text.find("\n3,0.025000");
  EXPECT_THAT(Error(text.substr(0, row + 60)), HasSubstr("line 11: the last row has"));
}

// An excerpt (the first frames of a take, the header's 'Total Exported Frames' left as it was) is a normal file:
// read whole, and marked incomplete with the header's count.
TEST(MotiveCsvTest, ReadsAnExcerptAndMarksItIncomplete) {
  const std::string text = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  const std::string excerpt = text.substr(0, text.find("\n3,0.025000") + 1);
  EXPECT_EQ(Error(excerpt), "");
  MotiveReader reader(excerpt, "excerpt.csv");
  const MotiveTakeSummary s = InspectMotiveTake(reader);
  EXPECT_EQ(s.frames, 3);
  EXPECT_FALSE(s.complete);
  EXPECT_EQ(s.frames_in_header, 499);
  MotiveReader again(excerpt, "excerpt.csv");
  const RigidBodyTrack track = ReadRigidBodyTrack(again, "ernesto_body");
  EXPECT_EQ(track.size(), 3u);
  EXPECT_FALSE(track.complete);
  // The whole file is complete.
  MotiveReader whole(text, "whole.csv");
  EXPECT_TRUE(InspectMotiveTake(whole).complete);
  // More rows than the header says the export wrote is not an excerpt: an edited or spliced file.
  std::string more = text;
  more.replace(more.find("Total Exported Frames,499"), 25, "Total Exported Frames,400");
  EXPECT_THAT(Error(more), HasSubstr("499 frames; the header's 'Total Exported Frames' is 400"));
}

TEST(MotiveCsvTest, RejectsNonIncreasingFrames) {
  const std::string text = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  const std::size_t row = text.find("\n3,0.025000");
  std::string bad = text;
  bad[row + 1] = '1';
  EXPECT_THAT(Error(bad), HasSubstr("does not follow frame 2"));
}

TEST(MotiveCsvTest, LfAndCrlfReadTheSame) {
  const std::string crlf = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  const std::string lf = std::regex_replace(crlf, std::regex("\r\n"), "\n");
  ASSERT_NE(lf.size(), crlf.size());
  MotiveReader a(crlf, "crlf"), b(lf, "lf");
  MotiveRow ra, rb;
  int n = 0;
  while (a.ReadFrame(ra)) {
    ASSERT_TRUE(b.ReadFrame(rb));
    const auto xa = a.RigidBodyPose(ra, 0), xb = b.RigidBodyPose(rb, 0);
    ASSERT_EQ(xa.has_value(), xb.has_value());
    if (xa) {
      EXPECT_TRUE(xa->isApprox(*xb, 0));
    }
    ++n;
  }
  EXPECT_EQ(n, 499);
}

// A spreadsheet re-save: trailing zeros dropped, trailing commas added, blank row written as commas, quotes gone.
TEST(MotiveCsvTest, ReadsSpreadsheetResave) {
  const std::string original = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  std::string resaved = std::regex_replace(original, std::regex("(\\.[0-9]*?)0+(,|\r)"), "$1$2");
  resaved = std::regex_replace(resaved, std::regex("\\.(,|\r)"), "$1");
  resaved = std::regex_replace(resaved, std::regex("\""), "");
  resaved = std::regex_replace(resaved, std::regex("\r\n"), ",,,\r\n");
  ASSERT_NE(resaved.find("120,Export"), std::string::npos);  // "120.000000" became "120"
  MotiveReader ra(original, "original.csv");
  const RigidBodyTrack a = ReadRigidBodyTrack(ra, "ernesto_body");
  MotiveReader rb(resaved, "resaved.csv");
  const RigidBodyTrack b = ReadRigidBodyTrack(rb, "ernesto_body");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.present[i], b.present[i]);
    if (a.present[i]) {
      EXPECT_TRUE(a.p_TB[i].isApprox(b.p_TB[i], 1e-15));
    }
  }
}

TEST(MotiveCsvTest, UnknownRigidBodyNamesTheOnesPresent) {
  try {
    ReadRigidBodyTrack(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"), "Ring");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no rigid body named 'Ring'"));
    EXPECT_THAT(e.what(), HasSubstr("'ernesto_body'"));
  }
}

// Synthetic exports: every rotation type and both length units give back the same poses.
class MotiveFlavourTest : public ::testing::TestWithParam<std::tuple<MotiveRotationType, bool>> {};

TEST_P(MotiveFlavourTest, PosesMatchTheQuaternionMetreExport) {
  const PoseTrajectory traj = testing::TestMotion(3.0);
  SyntheticTrackerOptions o;
  o.X_TF = PoseFromMmDeg((Vector6d() << 100, 200, 1500, 170, 10, 30).finished());
  o.position_noise_bound_m = o.rotation_noise_bound_rad = o.marker_noise_bound_m = 0;
  MotiveReader reference(testing::WriteTake(traj, o), "quaternion.csv");
  o.rotation_type = std::get<0>(GetParam());
  o.millimetres = std::get<1>(GetParam());
  o.crlf = false;
  MotiveReader flavour(testing::WriteTake(traj, o), "flavour.csv");
  EXPECT_EQ(flavour.header().rotation_type, o.rotation_type);
  EXPECT_DOUBLE_EQ(flavour.header().length_scale_to_m, o.millimetres ? 1e-3 : 1.0);
  MotiveRow ra, rb;
  int n = 0;
  while (reference.ReadFrame(ra)) {
    ASSERT_TRUE(flavour.ReadFrame(rb));
    const auto a = reference.RigidBodyPose(ra, 0), b = flavour.RigidBodyPose(rb, 0);
    ASSERT_TRUE(a && b);
    EXPECT_LT((a->translation() - b->translation()).norm(), 2e-6);  // 6 decimals in m
    EXPECT_LT(RotationAngleBetween(a->linear(), b->linear()), 1e-5);  // 6 decimals in quaternion / deg
    ++n;
  }
  EXPECT_GT(n, 300);
}

INSTANTIATE_TEST_SUITE_P(
    AllRotationTypes, MotiveFlavourTest,
    ::testing::Combine(::testing::Values(MotiveRotationType::kQuaternion, MotiveRotationType::kXYZ,
                                         MotiveRotationType::kXZY, MotiveRotationType::kYXZ,
                                         MotiveRotationType::kYZX, MotiveRotationType::kZXY,
                                         MotiveRotationType::kZYX),
                       ::testing::Bool()));

TEST(MotiveCsvTest, EulerRoundTripsForRandomRotations) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (MotiveRotationType type : {MotiveRotationType::kXYZ, MotiveRotationType::kXZY, MotiveRotationType::kYXZ,
                                  MotiveRotationType::kYZX, MotiveRotationType::kZXY, MotiveRotationType::kZYX}) {
    for (int i = 0; i < 200; ++i) {
      const Eigen::Matrix3d R = RotationFromVector(Eigen::Vector3d(u(gen), u(gen), u(gen)) / 1.8);
      const Eigen::Matrix3d back = RotationFromMotiveEuler(type, MotiveEulerFromRotation(type, R));
      EXPECT_LT(RotationAngleBetween(R, back), 1e-9) << RotationTypeName(type);
    }
  }
}

TEST(MotiveCsvTest, XyzOrderIsIntrinsicXThenYThenZ) {
  // Documented assumption (motive_csv.h): XYZ → R = Rx(x)·Ry(y)·Rz(z).
  const Eigen::Vector3d a(0.3, -0.2, 0.5);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ())).toRotationMatrix();
  EXPECT_TRUE(RotationFromMotiveEuler(MotiveRotationType::kXYZ, a).isApprox(expected, 1e-15));
}

TEST(MotiveCsvTest, CountsGapsAndFrameJumps) {
  const PoseTrajectory traj = testing::TestMotion(5.0);
  SyntheticTrackerOptions o;
  o.occlusion_gaps = 3;
  o.gap_min_s = 0.05;
  o.gap_max_s = 0.1;
  std::ostringstream out;
  const SyntheticRecording rec = WriteSyntheticMotiveCsv(traj, o, out);
  // Remove frames 100..109 from the file: an excerpt with a frame-number jump.
  std::string text = out.str();
  const std::size_t a = text.find("\r\n100,"), b = text.find("\r\n110,");
  text.erase(a, b - a);
  // The header's count stays as the export wrote it: the rows removed make this file incomplete.
  MotiveReader reader(text, "jump.csv");
  const MotiveTakeSummary s = InspectMotiveTake(reader);
  EXPECT_EQ(s.frames, rec.frames - 10);
  EXPECT_EQ(s.frame_jumps, 1);
  EXPECT_FALSE(s.complete);
  EXPECT_EQ(s.frames_in_header, rec.frames);
  EXPECT_EQ(s.rigid_bodies[0].gaps.frames_present, rec.frames - rec.frames_occluded - 10);
  EXPECT_GE(s.rigid_bodies[0].gaps.gaps, rec.gaps);  // the jump is one more gap unless it touches an occlusion
  EXPECT_LE(s.rigid_bodies[0].gaps.gaps, rec.gaps + 1);
}

TEST(MotiveCsvTest, ReadsSeveralRigidBodies) {
  // Two rigid bodies side by side (format 1.23 layout, as Motive writes takes with several assets).
  const std::string text =
      "Format Version,1.23,Take Name,two,Capture Frame Rate,100,Export Frame Rate,100,Rotation Type,Quaternion,"
      "Length Units,Millimeters,Coordinate Space,Global\n\n"
      ",Type,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,"
      "Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body\n"
      ",Name,A,A,A,A,A,A,A,B,B,B,B,B,B,B\n,ID,1,1,1,1,1,1,1,2,2,2,2,2,2,2\n"
      ",,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Rotation,Rotation,Rotation,Rotation,"
      "Position,Position,Position\n"
      "Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,X,Y,Z,W,X,Y,Z\n"
      "7,0.07,0,0,0,1,10,20,30,0,0,0.7071068,0.7071068,-5,0,1000\n"
      "8,0.08,,,,,,,,0,0,0.7071068,0.7071068,-5,0,1001\n";
  MotiveReader reader(text, "two.csv");
  ASSERT_EQ(reader.layout().rigid_bodies.size(), 2u);
  EXPECT_EQ(reader.layout().FindRigidBody("B"), 1);
  MotiveRow row;
  ASSERT_TRUE(reader.ReadFrame(row));
  EXPECT_DOUBLE_EQ(row.time_s, 0.07);
  const auto b = reader.RigidBodyPose(row, 1);
  ASSERT_TRUE(b);
  EXPECT_TRUE(b->translation().isApprox(Eigen::Vector3d(-0.005, 0, 1.0), 1e-15));
  EXPECT_NEAR(RotationVector(b->linear()).z(), kPi / 2, 1e-6);
  ASSERT_TRUE(reader.ReadFrame(row));
  EXPECT_FALSE(reader.RigidBodyPose(row, 0).has_value());
  EXPECT_TRUE(reader.RigidBodyPose(row, 1).has_value());
}

// A small take in the 1.23 layout (two rigid bodies) for the hostile cases below; `names` is the Name row.
std::string TwoBodyTake(const std::string& names = ",Name,A,A,A,A,A,A,A,B,B,B,B,B,B,B\n",
                        const std::string& rows = "7,0.07,0,0,0,1,10,20,30,0,0,0,1,-5,0,1000\n"
                                                  "8,0.08,0,0,0,1,11,20,30,0,0,0,1,-5,0,1001\n") {
  return "Format Version,1.23,Take Name,two,Capture Frame Rate,100,Export Frame Rate,100,Rotation Type,Quaternion,"
         "Length Units,Millimeters,Coordinate Space,Global\n\n"
         ",Type,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,"
         "Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body\n" +
         names + ",ID,1,1,1,1,1,1,1,2,2,2,2,2,2,2\n"
         ",,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Rotation,Rotation,Rotation,Rotation,"
         "Position,Position,Position\n"
         "Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,X,Y,Z,W,X,Y,Z\n" +
         rows;
}

// Motive exports go through the project's strict CSV splitter: the hostile cases of an edited or re-saved file.
TEST(MotiveCsvTest, HostileCellsAndHeadersAreErrorsOrReadExactly) {
  EXPECT_EQ(Error(TwoBodyTake()), "");
  // One extra cell with a value beyond the 16 header columns (trailing empty cells of a spreadsheet are fine).
  EXPECT_EQ(Error(TwoBodyTake(",Name,A,A,A,A,A,A,A,B,B,B,B,B,B,B\n",
                              "7,0.07,0,0,0,1,10,20,30,0,0,0,1,-5,0,1000,,,\n")), "");
  EXPECT_THAT(Error(TwoBodyTake(",Name,A,A,A,A,A,A,A,B,B,B,B,B,B,B\n", "7,0.07,0,0,0,1,10,20,30,0,0,0,1,-5,0,1000,4\n")),
              HasSubstr("take.csv line 8, column 17: got '4'; expected at most 16 cells, one per header column"));
  // A column named twice (B renamed A with A's ID would silently replace A's columns).
  const std::string twice = std::regex_replace(TwoBodyTake(",Name,A,A,A,A,A,A,A,A,A,A,A,A,A,A\n"),
                                               std::regex(",ID,1,1,1,1,1,1,1,2,2,2,2,2,2,2"),
                                               ",ID,1,1,1,1,1,1,1,1,1,1,1,1,1,1");
  EXPECT_THAT(Error(twice), HasSubstr("column 10 (Rigid Body 'A' Rotation X) repeats column 3"));
  // Time cells that go back while the frame numbers increase: an edited or spliced file.
  EXPECT_THAT(Error(TwoBodyTake(",Name,A,A,A,A,A,A,A,B,B,B,B,B,B,B\n",
                                "7,0.07,0,0,0,1,10,20,30,0,0,0,1,-5,0,1000\n"
                                "8,0.06,0,0,0,1,11,20,30,0,0,0,1,-5,0,1001\n")),
              HasSubstr("take.csv line 9, column 2 (Time): got '0.06'; expected a time greater than 0.07"));
  // A Type row longer than the axis row (found by fuzz_motive_reader: the Time check read past the axis row).
  const std::string short_axis = std::regex_replace(TwoBodyTake(), std::regex("\nFrame,[^\n]*\n"), "\nFrame\n");
  ASSERT_NE(short_axis, TwoBodyTake());
  EXPECT_THAT(Error(short_axis), HasSubstr("take.csv line 7: column 4 (Rigid Body 'A' Rotation ) repeats column 3"));
  // A frame count beyond any take (found by fuzz_motive_reader: 1.9e107 was converted to an integer, undefined
  // behaviour) or not whole.
  for (const std::string count : {"1.9e107", "2.5", "-1", "many"}) {
    const std::string text = std::regex_replace(TwoBodyTake(), std::regex("Coordinate Space"),
                                                "Total Exported Frames," + count + ",Coordinate Space");
    EXPECT_EQ(Error(text), "take.csv line 1: 'Total Exported Frames' is '" + count +
                               "'; expected a whole number of frames from 0 to 9e15");
  }
  // An unterminated quote names its line and field.
  EXPECT_THAT(Error(TwoBodyTake(",Name,A,A,A,A,A,A,A,B,B,B,B,B,B,B\n", "7,0.07,\"0,0,0,1,10,20,30,0,0,0,1,-5,0,1000\n")),
              HasSubstr("take.csv line 8, field 3: unterminated quote"));
  // A byte-order mark and quoted header cells read exactly as the plain file.
  const std::string plain = TwoBodyTake();
  const std::string quoted = std::regex_replace(
      plain, std::regex("(\n|,)(Rigid Body|Rotation|Position|Frame|Name|ID|X|Y|Z|W)(?=,|\n)"), "$1\"$2\"");
  ASSERT_NE(quoted, plain);
  for (const std::string& text : {"\xEF\xBB\xBF" + plain, quoted}) {
    MotiveReader a(plain, "plain.csv"), b(text, "variant.csv");
    ASSERT_EQ(b.layout().rigid_bodies.size(), 2u);
    MotiveRow ra, rb;
    while (a.ReadFrame(ra)) {
      ASSERT_TRUE(b.ReadFrame(rb));
      EXPECT_TRUE(a.RigidBodyPose(ra, 1)->isApprox(*b.RigidBodyPose(rb, 1), 0));
    }
    EXPECT_FALSE(b.ReadFrame(rb));
  }
}

// Real export 2 quotes its marker names ("ernesto_body:Marker1"): the names are read without the quotes, so the
// markers belong to their rigid body by name (before, the quotes stayed in the name and only the ID matched).
TEST(MotiveCsvTest, QuotedNamesInARealExportAreReadWithoutQuotes) {
  MotiveReader reader(ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv")), "real.csv");
  ASSERT_FALSE(reader.layout().rigid_body_markers.empty());
  EXPECT_EQ(reader.layout().rigid_body_markers[0].name, "ernesto_body:Marker1");
  EXPECT_EQ(reader.layout().rigid_bodies[0].id, "DF9A050D387F11EABB89D61D800D886");
  EXPECT_EQ(reader.layout().rigid_bodies[0].marker_indices.size(), 4u);
}

TEST(MotiveCsvTest, PoseFromMarkersWhenNoRigidBody) {
  // Real export 2 has the markers ernesto_body:Marker1..4; build the pose from them and compare the motion with
  // the solved rigid body: relative motions agree to the marker noise.
  const std::string text = ReadTextFile(DataFile("timeanddoctor_parse_optitrack_csv_test.csv"));
  // Hide the rigid body by renaming it in the Name row (the markers keep their names).
  std::string renamed = std::regex_replace(text, std::regex(",ernesto_body,ernesto_body,ernesto_body,ernesto_body,"
                                                            "ernesto_body,ernesto_body,ernesto_body,ernesto_body,"),
                                           ",hidden,hidden,hidden,hidden,hidden,hidden,hidden,hidden,");
  ASSERT_NE(renamed, text);
  MotiveReader solved_reader(text, "a"), markers_reader(renamed, "b");
  const RigidBodyTrack solved = ReadRigidBodyTrack(solved_reader, "ernesto_body");
  const RigidBodyTrack fitted = ReadRigidBodyTrack(markers_reader, "ernesto_body");
  EXPECT_EQ(fitted.source, "markers (4)");
  ASSERT_EQ(solved.size(), fitted.size());
  const Eigen::Quaterniond qs0 = solved.q_TB[0], qf0 = fitted.q_TB[0];
  for (std::size_t i = 1; i < solved.size(); ++i) {
    if (!solved.present[i] || !fitted.present[i]) continue;
    const double a = qs0.angularDistance(solved.q_TB[i]), b = qf0.angularDistance(fitted.q_TB[i]);
    EXPECT_NEAR(a, b, DegToRad(0.5));
  }
  EXPECT_LT(fitted.marker_fit_rms_m, 2e-3);
}

}  // namespace
}  // namespace robossis::calibration
