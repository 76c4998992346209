// The CPU line image the panel draws its slice and plots with (src/apps/panel/line_image.h): which pixels a line
// lights, its clipping, and the blending of translucent lines.
#include "src/apps/panel/line_image.h"

#include <gtest/gtest.h>

namespace robossis::apps {
namespace {

constexpr ImU32 kRed = IM_COL32(255, 0, 0, 255);

TEST(LineImage, AHorizontalLineLightsItsPixelsButTheLast) {
  LineImage image;
  image.Reset(ImVec2(10, 20), ImVec2(30, 30));
  EXPECT_EQ(image.width(), 20);
  EXPECT_EQ(image.height(), 10);
  image.AddLine(ImVec2(12, 25), ImVec2(17, 25), kRed);
  for (int x = 12; x < 17; ++x) EXPECT_EQ(image.At(x, 25), kRed) << x;
  EXPECT_EQ(image.At(17, 25), 0u);  // the last pixel is left out, as GL does
  EXPECT_EQ(image.At(11, 25), 0u);
  EXPECT_EQ(image.At(14, 24), 0u);
  EXPECT_EQ(image.At(14, 26), 0u);
}

TEST(LineImage, ADiagonalLineLightsOnePixelPerStep) {
  LineImage image;
  image.Reset(ImVec2(0, 0), ImVec2(10, 10));
  image.AddLine(ImVec2(1, 1), ImVec2(6, 6), kRed);
  int lit = 0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) lit += image.At(x, y) != 0;
  EXPECT_EQ(lit, 5);
  for (int k = 1; k < 6; ++k) EXPECT_EQ(image.At(k, k), kRed) << k;
}

TEST(LineImage, LinesAreClippedToThePicture) {
  LineImage image;
  image.Reset(ImVec2(0, 0), ImVec2(8, 4));
  image.AddLine(ImVec2(-100, 2), ImVec2(100, 2), kRed);     // across it
  image.AddLine(ImVec2(-50, -50), ImVec2(-40, -40), kRed);  // wholly outside
  for (int x = 0; x < 8; ++x) EXPECT_EQ(image.At(x, 2), kRed) << x;
  EXPECT_EQ(image.At(0, 1), 0u);
  EXPECT_EQ(image.line_count(), 2u);
}

TEST(LineImage, TheBackgroundFillsThePictureAndOpaqueLinesReplaceIt) {
  LineImage image;
  const ImU32 background = IM_COL32(20, 22, 28, 255);
  image.Reset(ImVec2(0, 0), ImVec2(4, 4), background);
  image.AddLine(ImVec2(0, 1), ImVec2(3, 1), kRed);
  EXPECT_EQ(image.At(0, 0), background);
  EXPECT_EQ(image.At(1, 1), kRed);
}

TEST(LineImage, TheRowsALineLitAreKnownUntilTheNextReset) {
  LineImage image;
  image.Reset(ImVec2(0, 10), ImVec2(8, 20));
  image.AddLine(ImVec2(0, 13), ImVec2(8, 13), kRed);  // row 3 of the picture
  image.AddLine(ImVec2(2, 30), ImVec2(6, 30), kRed);  // below it: lights nothing
  for (int y = 0; y < 10; ++y) EXPECT_EQ(image.row_lit(y), y == 3) << y;
  EXPECT_FALSE(image.row_lit(-1));
  EXPECT_FALSE(image.row_lit(10));
  image.Reset(ImVec2(0, 10), ImVec2(8, 20));
  EXPECT_FALSE(image.row_lit(3));
}

// Two translucent lines over one pixel, then the image over a background with ImGui's blending (source alpha, one
// minus source alpha), give what the two lines blended straight onto the background give.
TEST(LineImage, TranslucentLinesComposeAsIfDrawnOneAfterTheOther) {
  LineImage image;
  image.Reset(ImVec2(0, 0), ImVec2(4, 4));
  const ImU32 blue = IM_COL32(90, 200, 255, 60), green = IM_COL32(0, 255, 0, 128);
  image.AddLine(ImVec2(0, 0), ImVec2(3, 0), blue);
  image.AddLine(ImVec2(1, 0), ImVec2(1, 3), green);
  const ImU32 pixel = image.At(1, 0);
  const double background[3] = {40, 30, 20};
  auto channel = [](ImU32 c, int shift) { return static_cast<double>((c >> shift) & 0xFF); };
  const int shifts[3] = {IM_COL32_R_SHIFT, IM_COL32_G_SHIFT, IM_COL32_B_SHIFT};
  const double a_image = channel(pixel, IM_COL32_A_SHIFT) / 255;
  for (int k = 0; k < 3; ++k) {
    double direct = background[k];
    for (const ImU32 line : {blue, green}) {
      const double a = channel(line, IM_COL32_A_SHIFT) / 255;
      direct = channel(line, shifts[k]) * a + direct * (1 - a);
    }
    const double composed = channel(pixel, shifts[k]) * a_image + background[k] * (1 - a_image);
    EXPECT_NEAR(composed, direct, 1.5) << "channel " << k;
  }
  EXPECT_EQ(image.At(3, 3), 0u);  // untouched pixels stay transparent
}

}  // namespace
}  // namespace robossis::apps
