#include "src/apps/panel/direct_draw.h"

#define GL_GLEXT_PROTOTYPES  // the OpenGL 3.3 entry points, which Mesa's libGL exports
#include <GLFW/glfw3.h>      // GL/gl.h
#include <GL/glext.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace robossis::apps {
namespace {

// ImGui's orthographic projection of the display rectangle (x0, y0, width, height), y down.
constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec2 position;
layout(location = 1) in vec4 color;
uniform vec4 display;
out vec4 frag_color;
void main() {
  frag_color = color;
  gl_Position = vec4(2.0 * (position.x - display.x) / display.z - 1.0,
                     1.0 - 2.0 * (position.y - display.y) / display.w, 0.0, 1.0);
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
in vec4 frag_color;
out vec4 out_color;
void main() { out_color = frag_color; }
)";

// The image, texel for pixel (nearest filtering on a 1:1 quad). A plain copy of an interpolated texture
// coordinate's texel, so that llvmpipe can treat it as a blit.
constexpr const char* kImageVertexShader = R"(#version 330 core
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 uv;
uniform vec4 display;
out vec2 frag_uv;
void main() {
  frag_uv = uv;
  gl_Position = vec4(2.0 * (position.x - display.x) / display.z - 1.0,
                     1.0 - 2.0 * (position.y - display.y) / display.w, 0.0, 1.0);
}
)";

constexpr const char* kImageFragmentShader = R"(#version 330 core
uniform sampler2D image;
in vec2 frag_uv;
out vec4 out_color;
void main() { out_color = texture(image, frag_uv); }
)";

GLuint Compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("panel: the direct-draw shader does not compile: ") + log);
  }
  return shader;
}

GLuint Link(const char* vertex_source, const char* fragment_source) {
  const GLuint vertex = Compile(GL_VERTEX_SHADER, vertex_source);
  GLuint fragment = 0;
  try {
    fragment = Compile(GL_FRAGMENT_SHADER, fragment_source);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw std::runtime_error(std::string("panel: the direct-draw shaders do not link: ") + log);
  }
  return program;
}

}  // namespace

DirectRenderer::DirectRenderer() {
  program_ = Link(kVertexShader, kFragmentShader);
  try {
    image_program_ = Link(kImageVertexShader, kImageFragmentShader);
  } catch (...) {
    glDeleteProgram(program_);
    throw;
  }
  display_location_ = glGetUniformLocation(program_, "display");
  image_display_location_ = glGetUniformLocation(image_program_, "display");
  glUseProgram(image_program_);
  glUniform1i(glGetUniformLocation(image_program_, "image"), 0);  // texture unit 0, as ImGui's
  glUseProgram(0);
  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(1, &vertex_buffer_);
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(DirectVertex),
                        reinterpret_cast<const void*>(offsetof(DirectVertex, x)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(DirectVertex),
                        reinterpret_cast<const void*>(offsetof(DirectVertex, color)));
  glGenVertexArrays(1, &image_vertex_array_);
  glGenBuffers(1, &image_vertex_buffer_);
  glBindVertexArray(image_vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, image_vertex_buffer_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), reinterpret_cast<const void*>(2 * sizeof(float)));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

DirectRenderer::~DirectRenderer() {
  glDeleteBuffers(1, &vertex_buffer_);
  glDeleteBuffers(1, &image_vertex_buffer_);
  glDeleteVertexArrays(1, &image_vertex_array_);
  glDeleteVertexArrays(1, &vertex_array_);
  glDeleteProgram(program_);
  glDeleteProgram(image_program_);
}

void DirectRenderer::Submit(ImDrawList* draw, DirectBatch& batch) {
  if (batch.triangles_.empty()) return;
  batch.renderer_ = this;
  draw->AddCallback(&DirectRenderer::Callback, &batch);
  draw->AddCallback(ImDrawCallback_ResetRenderState, nullptr);  // ImGui's program, buffers and blending again
}

void DirectRenderer::Submit(ImDrawList* draw, ImageTexture& image) {
  if (image.width_ == 0 || image.height_ == 0) return;
  image.renderer_ = this;
  draw->AddCallback(&DirectRenderer::ImageCallback, &image);
  draw->AddCallback(ImDrawCallback_ResetRenderState, nullptr);
}

void DirectRenderer::ImageCallback(const ImDrawList*, const ImDrawCmd* command) {
  const auto* image = static_cast<const ImageTexture*>(command->UserCallbackData);
  image->renderer_->Draw(*image, *command);
}

bool DirectRenderer::Clip(const ImDrawCmd& command, float display[4]) const {
  const ImDrawData* data = ImGui::GetDrawData();
  const ImVec2 pos = data->DisplayPos, size = data->DisplaySize, scale = data->FramebufferScale;
  // The clip rectangle in framebuffer pixels, rows from the bottom (as ImGui's OpenGL 3 back end sets it).
  const float x0 = (command.ClipRect.x - pos.x) * scale.x, y0 = (command.ClipRect.y - pos.y) * scale.y;
  const float x1 = (command.ClipRect.z - pos.x) * scale.x, y1 = (command.ClipRect.w - pos.y) * scale.y;
  if (x1 <= x0 || y1 <= y0) return false;
  glEnable(GL_SCISSOR_TEST);
  glScissor(static_cast<GLint>(x0), static_cast<GLint>(size.y * scale.y - y1), static_cast<GLsizei>(x1 - x0),
            static_cast<GLsizei>(y1 - y0));
  display[0] = pos.x;
  display[1] = pos.y;
  display[2] = size.x;
  display[3] = size.y;
  return true;
}

void DirectRenderer::Draw(const ImageTexture& image, const ImDrawCmd& command) {
  float display[4];
  if (!Clip(command, display)) return;
  const ImDrawData* data = ImGui::GetDrawData();
  if (data->FramebufferScale.x != 1 || data->FramebufferScale.y != 1) return;  // 1:1 texels need a 1:1 framebuffer
  glUseProgram(image_program_);
  glUniform4f(image_display_location_, display[0], display[1], display[2], display[3]);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, image.texture_);
  if (image.bands_.empty()) return;
  const float x0 = static_cast<float>(image.x0_), x1 = x0 + static_cast<float>(image.width_);
  const float h = static_cast<float>(image.height_);
  std::vector<std::array<float, 4>>& quads = image_vertices_;  // x, y, u, v
  quads.clear();
  for (const std::array<int, 2>& band : image.bands_) {
    const float y0 = static_cast<float>(image.y0_ + band[0]), y1 = static_cast<float>(image.y0_ + band[1]);
    const float v0 = static_cast<float>(band[0]) / h, v1 = static_cast<float>(band[1]) / h;
    for (const std::array<float, 4>& corner : {std::array<float, 4>{x0, y0, 0, v0}, {x1, y0, 1, v0}, {x1, y1, 1, v1},
                                               {x0, y0, 0, v0}, {x1, y1, 1, v1}, {x0, y1, 0, v1}})
      quads.push_back(corner);
  }
  glBindVertexArray(image_vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, image_vertex_buffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads.size() * sizeof(quads[0])), quads.data(),
               GL_STREAM_DRAW);
  glDisable(GL_BLEND);  // opaque
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(quads.size()));
}

void DirectRenderer::Callback(const ImDrawList*, const ImDrawCmd* command) {
  const auto* batch = static_cast<const DirectBatch*>(command->UserCallbackData);
  batch->renderer_->Draw(*batch, *command);
}

void DirectRenderer::Draw(const DirectBatch& batch, const ImDrawCmd& command) {
  float display[4];
  if (!Clip(command, display)) return;
  glUseProgram(program_);
  glUniform4f(display_location_, display[0], display[1], display[2], display[3]);
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  const std::size_t triangles = batch.triangles_.size();
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles * sizeof(DirectVertex)), batch.triangles_.data(),
               GL_STREAM_DRAW);
  glDisable(GL_BLEND);  // opaque: no framebuffer read per pixel
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles));
}

ImageTexture::~ImageTexture() {
  if (texture_ != 0) glDeleteTextures(1, &texture_);
}

void ImageTexture::Draw(ImDrawList* draw, DirectRenderer& gl, const LineImage& image, bool only_lit_rows) {
  if (image.width() == 0 || image.height() == 0) return;
  if (texture_ == 0) {
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // 1:1: a texel is a pixel
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  x0_ = image.x0();
  y0_ = image.y0();
  bands_.clear();
  for (int first = 0; first < image.height(); first += kBandRows) {
    const int end = std::min(image.height(), first + kBandRows);
    bool lit = !only_lit_rows;
    for (int y = first; y < end && !lit; ++y) lit = image.row_lit(y);
    if (!lit) continue;
    if (!bands_.empty() && bands_.back()[1] == first)
      bands_.back()[1] = end;  // one quad for neighbouring bands
    else
      bands_.push_back({first, end});
  }
  if (image.width() != width_ || image.height() != height_) {
    width_ = image.width();
    height_ = image.height();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width_, height_, 0, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels().data());
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels().data());
  }
  gl.Submit(draw, *this);
}

void ImageTexture::Redraw(ImDrawList* draw, DirectRenderer& gl) {
  if (texture_ != 0) gl.Submit(draw, *this);
}

}  // namespace robossis::apps
