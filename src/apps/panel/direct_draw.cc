#include "src/apps/panel/direct_draw.h"

#define GL_GLEXT_PROTOTYPES  // the OpenGL 3.3 entry points, which Mesa's libGL exports
#include <GLFW/glfw3.h>      // GL/gl.h
#include <GL/glext.h>

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

}  // namespace

DirectRenderer::DirectRenderer() {
  const GLuint vertex = Compile(GL_VERTEX_SHADER, kVertexShader);
  GLuint fragment = 0;
  try {
    fragment = Compile(GL_FRAGMENT_SHADER, kFragmentShader);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vertex);
  glAttachShader(program_, fragment);
  glLinkProgram(program_);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    glDeleteProgram(program_);
    throw std::runtime_error(std::string("panel: the direct-draw shaders do not link: ") + log);
  }
  display_location_ = glGetUniformLocation(program_, "display");
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
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

DirectRenderer::~DirectRenderer() {
  glDeleteBuffers(1, &vertex_buffer_);
  glDeleteVertexArrays(1, &vertex_array_);
  glDeleteProgram(program_);
}

void DirectRenderer::Submit(ImDrawList* draw, DirectBatch& batch) {
  if (batch.lines_.empty() && batch.triangles_.empty()) return;
  batch.renderer_ = this;
  draw->AddCallback(&DirectRenderer::Callback, &batch);
  draw->AddCallback(ImDrawCallback_ResetRenderState, nullptr);  // ImGui's program, buffers and blending again
}

void DirectRenderer::Callback(const ImDrawList*, const ImDrawCmd* command) {
  const auto* batch = static_cast<const DirectBatch*>(command->UserCallbackData);
  batch->renderer_->Draw(*batch, *command);
}

void DirectRenderer::Draw(const DirectBatch& batch, const ImDrawCmd& command) {
  const ImDrawData* data = ImGui::GetDrawData();
  const ImVec2 pos = data->DisplayPos, size = data->DisplaySize, scale = data->FramebufferScale;
  // The clip rectangle in framebuffer pixels, rows from the bottom (as ImGui's OpenGL 3 back end sets it).
  const float x0 = (command.ClipRect.x - pos.x) * scale.x, y0 = (command.ClipRect.y - pos.y) * scale.y;
  const float x1 = (command.ClipRect.z - pos.x) * scale.x, y1 = (command.ClipRect.w - pos.y) * scale.y;
  if (x1 <= x0 || y1 <= y0) return;
  glEnable(GL_SCISSOR_TEST);
  glScissor(static_cast<GLint>(x0), static_cast<GLint>(size.y * scale.y - y1), static_cast<GLsizei>(x1 - x0),
            static_cast<GLsizei>(y1 - y0));
  glUseProgram(program_);
  glUniform4f(display_location_, pos.x, pos.y, size.x, size.y);
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  const std::size_t lines = batch.lines_.size(), triangles = batch.triangles_.size();
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>((triangles + lines) * sizeof(DirectVertex)), nullptr,
               GL_STREAM_DRAW);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(triangles * sizeof(DirectVertex)),
                  batch.triangles_.data());
  glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(triangles * sizeof(DirectVertex)),
                  static_cast<GLsizeiptr>(lines * sizeof(DirectVertex)), batch.lines_.data());
  if (triangles > 0) {
    glDisable(GL_BLEND);  // opaque: no framebuffer read per pixel
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles));
  }
  if (lines > 0) {
    glEnable(GL_BLEND);  // ImGui's blend function is still set
    glLineWidth(1.0f);
    glDrawArrays(GL_LINES, static_cast<GLint>(triangles), static_cast<GLsizei>(lines));
  }
}

ImageTexture::~ImageTexture() {
  if (texture_ != 0) glDeleteTextures(1, &texture_);
}

void ImageTexture::Draw(ImDrawList* draw, const LineImage& image) {
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
  if (image.width() != width_ || image.height() != height_) {
    width_ = image.width();
    height_ = image.height();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width_, height_, 0, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels().data());
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels().data());
  }
  const ImVec2 min(static_cast<float>(image.x0()), static_cast<float>(image.y0()));
  draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture_)), min,
                 ImVec2(min.x + static_cast<float>(width_), min.y + static_cast<float>(height_)));
}

}  // namespace robossis::apps
