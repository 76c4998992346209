#pragma once
// What OpenGL draws directly for the panel, in Dear ImGui's draw order (ImDrawList callbacks): flat opaque triangles
// (the bone fragments' thousands), and line images (line_image.h) as opaque textured quads (the workspace slice's
// edges, the plots).
//
// Why: on Mesa's software renderer (llvmpipe) the rasteriser's cost follows the primitives and the 4x4 pixel
// blocks each one touches, not the pixels lit. An ImGui triangle goes through ImGui's shader (a bilinear texture
// fetch and blending for every pixel); the shader here fetches no texture, and the triangles are drawn without
// blending (they are opaque). The picture is the same: the same screen positions and colours, in the same order.

#include <array>
#include <vector>

#include <imgui.h>

#include "src/apps/panel/line_image.h"

namespace robossis::apps {

// A vertex in ImGui's screen coordinates (pixels, y down) with ImGui's packed RGBA colour.
struct DirectVertex {
  float x, y;
  ImU32 color;
};

class DirectRenderer;
class ImageTexture;

// One batch of opaque triangles, filled while a frame is laid out and drawn in their order when ImGui renders the
// frame. It must live until the frame is rendered.
class DirectBatch {
 public:
  void Clear() { triangles_.clear(); }
  // An opaque triangle (the colour's alpha is ignored), as ImDrawList::AddTriangleFilled without anti-aliasing.
  void AddTriangle(ImVec2 a, ImVec2 b, ImVec2 c, ImU32 color) {
    triangles_.push_back({a.x, a.y, color});
    triangles_.push_back({b.x, b.y, color});
    triangles_.push_back({c.x, c.y, color});
  }
  std::size_t triangle_count() const { return triangles_.size() / 3; }

 private:
  friend class DirectRenderer;
  std::vector<DirectVertex> triangles_;
  DirectRenderer* renderer_ = nullptr;
};

// The shader program and vertex buffer. Needs the window's OpenGL 3.3 context current, in construction and
// destruction.
class DirectRenderer {
 public:
  // Compiles the shaders; throws std::runtime_error with the compiler's log when they do not compile or link.
  DirectRenderer();
  ~DirectRenderer();
  DirectRenderer(const DirectRenderer&) = delete;
  DirectRenderer& operator=(const DirectRenderer&) = delete;

  // Appends `batch` to `draw` at this point of its order, clipped to its current clip rectangle (and ImGui's own
  // render state restored after it).
  void Submit(ImDrawList* draw, DirectBatch& batch);
  // The same for an uploaded image, drawn 1:1 without blending (ImageTexture::Draw calls it).
  void Submit(ImDrawList* draw, ImageTexture& image);

 private:
  static void Callback(const ImDrawList* list, const ImDrawCmd* command);
  static void ImageCallback(const ImDrawList* list, const ImDrawCmd* command);
  void Draw(const DirectBatch& batch, const ImDrawCmd& command);
  void Draw(const ImageTexture& image, const ImDrawCmd& command);
  // Scissor from the command's clip rectangle, the display rectangle; false when nothing is visible.
  bool Clip(const ImDrawCmd& command, float display[4]) const;

  unsigned image_program_ = 0;  // the texel at the interpolated coordinate, nearest
  unsigned image_vertex_array_ = 0, image_vertex_buffer_ = 0;
  std::vector<std::array<float, 4>> image_vertices_;  // scratch, reused every frame
  int image_display_location_ = -1;
  unsigned program_ = 0;
  unsigned vertex_array_ = 0;
  unsigned vertex_buffer_ = 0;
  int display_location_ = -1;
};

// An opaque LineImage (one reset with an opaque background) as an OpenGL texture, drawn 1:1 at its screen place
// without blending, in ImGui's draw order: one quad for all its lines, and no framebuffer read per pixel (measured
// on llvmpipe: ImGui's textured, blended quad cost ~25 ns per pixel).
class ImageTexture {
 public:
  ImageTexture() = default;
  ~ImageTexture();  // the window's OpenGL context current
  ImageTexture(const ImageTexture&) = delete;
  ImageTexture& operator=(const ImageTexture&) = delete;
  // Uploads the picture (the window's OpenGL context current) and adds it to `draw` at this point of its order.
  // With only_lit_rows, only the bands of kBandRows rows where a line lit a pixel are drawn: for a picture whose
  // background is the one glClear already painted, the same picture with fewer pixels to shade.
  void Draw(ImDrawList* draw, DirectRenderer& gl, const LineImage& image, bool only_lit_rows = false);
  static constexpr int kBandRows = 8;  // [assumed] two 4x4 rasteriser blocks high
  // Adds the picture last uploaded again (nothing when none was).
  void Redraw(ImDrawList* draw, DirectRenderer& gl);

 private:
  friend class DirectRenderer;
  DirectRenderer* renderer_ = nullptr;
  unsigned texture_ = 0;
  int x0_ = 0, y0_ = 0, width_ = 0, height_ = 0;
  std::vector<std::array<int, 2>> bands_;  // the row ranges [first, end) to draw
};

}  // namespace robossis::apps
