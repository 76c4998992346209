#pragma once
// 1 px lines rasterised on the CPU into a small image, which the panel then draws as one textured quad: for the
// parts with thousands of short lines (the workspace slice's edges, the plots). On Mesa's software renderer each
// line is a primitive costing about a microsecond of setup and binning whatever its length (measured: the panel
// section of BENCHMARKS.md), while blending a 2-20 px line into memory here is a few nanoseconds per pixel.
//
// The picture is what GL would draw for the same lines one after the other with ImGui's blending (source alpha,
// one minus source alpha): the image keeps straight (not premultiplied) colours and its alpha, so drawing it once
// with that blending over the background gives the same colours (up to 8-bit rounding) as drawing each line.

#include <cstdint>
#include <vector>

#include <imgui.h>

namespace robossis::apps {

class LineImage {
 public:
  // A new picture over the screen rectangle from `min` to `max` (ImGui coordinates, rounded out to whole pixels),
  // filled with `background` (transparent by default). The pixels keep their memory between pictures.
  void Reset(ImVec2 min, ImVec2 max, ImU32 background = 0);
  // Blends a 1 px line from a to b: the pixels floor(p) along it (as ImDrawList::AddLine centres a 1 px line on
  // p + 0.5), the last one left out (GL's rule, so that a polyline's joints are drawn once), clipped to the
  // picture.
  void AddLine(ImVec2 a, ImVec2 b, ImU32 color);
  void AddPolyline(const ImVec2* points, int count, ImU32 color);

  int x0() const { return x0_; }
  int y0() const { return y0_; }
  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t line_count() const { return lines_; }
  // Row-major from the top, ImGui's packed RGBA (straight alpha).
  const std::vector<ImU32>& pixels() const { return pixels_; }
  // Whether a line lit a pixel of row y (from the top of the picture) since Reset.
  bool row_lit(int y) const { return y >= 0 && y < height_ && lit_rows_[static_cast<std::size_t>(y)] != 0; }
  // The pixel at screen position (x, y); 0 outside the picture.
  ImU32 At(int x, int y) const;

 private:
  void Blend(int x, int y, ImU32 color);

  int x0_ = 0, y0_ = 0, width_ = 0, height_ = 0;
  std::size_t lines_ = 0;
  std::vector<ImU32> pixels_;
  std::vector<std::uint8_t> lit_rows_;
};

}  // namespace robossis::apps
