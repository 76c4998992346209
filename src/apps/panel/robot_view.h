#pragma once
// The robot in 3-D for the panel, drawn with Dear ImGui's draw lists (lines and filled triangles projected by an
// orbit camera; no OpenGL state of its own): fixed and moving rings, the three arms, the bone fragments, the live
// workspace boundary slice around the ring, and the force and torque on the hand as arrows at the ring's centre.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <imgui.h>

#include "robot/rsr_model.h"
#include "src/apps/panel/direct_draw.h"
#include "src/panel/panel_backend.h"
#include "src/panel/panel_controller.h"

namespace robossis::apps {

// The panel's background, which glClear paints and the 3-D view shares (its slice image is opaque over it).
inline constexpr ImU32 kPanelBackground = IM_COL32(26, 26, 31, 255);

// A mesh reduced for drawing: vertices and triangles (in its own frame).
struct DrawMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

struct RobotScene {
  DrawMesh proximal_F;  // fixed to the fixed ring
  DrawMesh distal_M;    // fixed to the moving ring
  // The boundary of the dexterous slice at the current orientation: the positions the ring centre P can reach (F).
  std::vector<std::array<Eigen::Vector3d, 2>> slice_edges_F;
  std::uint64_t slice_generation = 0;  // counts the changes of slice_edges_F
};

// A coarser closed mesh of at most `max_triangles` (vertex clustering on a grid), for a frame-time budget on a
// software renderer.
DrawMesh ReduceForDrawing(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<std::array<int, 3>>& triangles, std::size_t max_triangles);
// The unique edges of a closed triangle mesh (vertices in m), at most `max_edges` of them.
std::vector<std::array<Eigen::Vector3d, 2>> MeshEdges(const std::vector<Eigen::Vector3d>& vertices,
                                                      const std::vector<Eigen::Vector3i>& triangles,
                                                      std::size_t max_edges);

// The view's many-primitive parts, drawn by OpenGL directly (direct_draw.h): refilled every frame.
struct RobotViewBatches {
  LineImage slice;             // the slice's edges (line_image.h)
  ImageTexture slice_texture;  // ... drawn as one quad
  // What the slice image was drawn for: it is drawn again only when one of them changes (the slice is in F: the
  // moving ring does not move it).
  struct SliceKey {
    std::uint64_t generation = 0;
    double azimuth_deg = 0, elevation_deg = 0, distance_mm = 0;
    float x = 0, y = 0, width = 0, height = 0;
    bool operator==(const SliceKey&) const = default;
  };
  SliceKey slice_key;
  bool slice_drawn = false;
  DirectBatch bone;            // the fragments' triangles, painter's order
  std::vector<ImVec2> scratch;  // the slice's projected edges
};

// Draws over the rectangle (origin, size) without filling it: the caller paints the background (the panel window
// clears it with glClear, far cheaper than a filled quad on a software renderer). The slice (an image of its edges)
// and the bone (through `gl`) are drawn from `batches`, which must live until the frame is rendered.
void DrawRobotView(ImDrawList* draw, DirectRenderer& gl, RobotViewBatches& batches, ImVec2 origin, ImVec2 size,
                   const panel::Camera& camera, const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                   const Eigen::Isometry3d& X_FM_commanded, const RobotScene& scene, const panel::HandWrench& wrench);

}  // namespace robossis::apps
