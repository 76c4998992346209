#include "src/apps/panel/line_image.h"

#include <algorithm>
#include <cmath>

namespace robossis::apps {

void LineImage::Reset(ImVec2 min, ImVec2 max, ImU32 background) {
  x0_ = static_cast<int>(std::floor(min.x));
  y0_ = static_cast<int>(std::floor(min.y));
  width_ = std::max(0, static_cast<int>(std::ceil(max.x)) - x0_);
  height_ = std::max(0, static_cast<int>(std::ceil(max.y)) - y0_);
  lines_ = 0;
  pixels_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), background);
  lit_rows_.assign(static_cast<std::size_t>(height_), 0);
}

ImU32 LineImage::At(int x, int y) const {
  x -= x0_;
  y -= y0_;
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0;
  return pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
}

void LineImage::Blend(int x, int y, ImU32 color) {
  x -= x0_;
  y -= y0_;
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  lit_rows_[static_cast<std::size_t>(y)] = 1;
  ImU32& pixel = pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
  const unsigned a = (color >> IM_COL32_A_SHIFT) & 0xFF;
  if (a == 255 || pixel == 0) {
    pixel = color;
    return;
  }
  // "Over" in straight alpha: A = a + A_d (1 - a), C = (c a + C_d A_d (1 - a)) / A (8-bit, with 255 as 1).
  const unsigned ad = (pixel >> IM_COL32_A_SHIFT) & 0xFF;
  const unsigned below = ad * (255 - a);  // A_d (1 - a), scaled by 255^2
  const unsigned out_a255 = a * 255 + below;  // A, scaled by 255^2
  if (out_a255 == 0) return;
  ImU32 out = 0;
  for (const int shift : {IM_COL32_R_SHIFT, IM_COL32_G_SHIFT, IM_COL32_B_SHIFT}) {
    const unsigned c = (color >> shift) & 0xFF, cd = (pixel >> shift) & 0xFF;
    const unsigned value = (c * a * 255 + cd * below + out_a255 / 2) / out_a255;
    out |= std::min(255u, value) << shift;
  }
  out |= ((out_a255 + 127) / 255) << IM_COL32_A_SHIFT;
  pixel = out;
}

void LineImage::AddLine(ImVec2 a, ImVec2 b, ImU32 color) {
  ++lines_;
  const float dx = b.x - a.x, dy = b.y - a.y;
  const int steps = static_cast<int>(std::ceil(std::max(std::abs(dx), std::abs(dy))));
  if (steps == 0) return;  // a zero-length line draws nothing (GL's rule too)
  // Clipped cheaply: a line wholly outside the picture costs two comparisons per axis.
  if (std::max(a.x, b.x) < static_cast<float>(x0_) || std::min(a.x, b.x) >= static_cast<float>(x0_ + width_) ||
      std::max(a.y, b.y) < static_cast<float>(y0_) || std::min(a.y, b.y) >= static_cast<float>(y0_ + height_))
    return;
  const float sx = dx / static_cast<float>(steps), sy = dy / static_cast<float>(steps);
  for (int k = 0; k < steps; ++k) {
    Blend(static_cast<int>(std::floor(a.x + sx * static_cast<float>(k))),
          static_cast<int>(std::floor(a.y + sy * static_cast<float>(k))), color);
  }
}

void LineImage::AddPolyline(const ImVec2* points, int count, ImU32 color) {
  for (int i = 1; i < count; ++i) AddLine(points[i - 1], points[i], color);
}

}  // namespace robossis::apps
