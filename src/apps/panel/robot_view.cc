#include "src/apps/panel/robot_view.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "src/core/units.h"

namespace robossis::apps {
namespace {

// Display scales of the arrows. [assumed] chosen so that the sigma.7's peak force (20 N) and torque (0.4 N·m)
// reach about 200 mm on the screen, comparable to the ring radius.
constexpr double kForceArrowMPerN = 0.010;
constexpr double kTorqueArrowMPerNm = 0.5;

struct Projector {
  Eigen::Vector3d eye, right, up, forward;
  ImVec2 center;
  double focal_px;
  bool Project(const Eigen::Vector3d& p_F, ImVec2& out, double* depth = nullptr) const {
    const Eigen::Vector3d d = p_F - eye;
    const double z = d.dot(forward);
    if (z < 1e-3) return false;
    out = ImVec2(static_cast<float>(center.x + focal_px * d.dot(right) / z),
                 static_cast<float>(center.y - focal_px * d.dot(up) / z));
    if (depth) *depth = z;
    return true;
  }
};

Projector MakeProjector(ImVec2 origin, ImVec2 size, const panel::Camera& camera, const Eigen::Vector3d& target) {
  const double az = DegToRad(camera.azimuth_deg), el = DegToRad(camera.elevation_deg);
  const double r = MmToM(camera.distance_mm);
  Projector p;
  p.eye = target + r * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  p.forward = (target - p.eye).normalized();
  const Eigen::Vector3d world_up = Eigen::Vector3d::UnitZ();
  p.right = p.forward.cross(world_up);
  if (p.right.norm() < 1e-9) p.right = Eigen::Vector3d::UnitX();
  p.right.normalize();
  p.up = p.right.cross(p.forward);
  p.center = ImVec2(origin.x + size.x / 2, origin.y + size.y / 2);
  p.focal_px = size.y / (2 * std::tan(DegToRad(20)));  // a 40 deg vertical field of view
  return p;
}

void Line(ImDrawList* draw, const Projector& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, ImU32 color,
          float thickness) {
  ImVec2 sa, sb;
  if (p.Project(a, sa) && p.Project(b, sb)) draw->AddLine(sa, sb, color, thickness);
}

void Ring(ImDrawList* draw, const Projector& p, const Eigen::Isometry3d& X, double radius, ImU32 color) {
  constexpr int kSegments = 72;
  Eigen::Vector3d last = X * Eigen::Vector3d(radius, 0, 0);
  for (int k = 1; k <= kSegments; ++k) {
    const double a = 2 * kPi * k / kSegments;
    const Eigen::Vector3d next = X * Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), 0);
    Line(draw, p, last, next, color, 4.0f);
    last = next;
  }
}

void Arrow(ImDrawList* draw, const Projector& p, const Eigen::Vector3d& from, const Eigen::Vector3d& vector,
           ImU32 color) {
  if (vector.norm() < 1e-6) return;
  const Eigen::Vector3d to = from + vector;
  ImVec2 a, b;
  if (!p.Project(from, a) || !p.Project(to, b)) return;
  draw->AddLine(a, b, color, 3.0f);
  const float dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
  if (len < 1) return;
  const float ux = dx / len, uy = dy / len, head = 12;
  draw->AddTriangleFilled(b, ImVec2(b.x - head * ux + 0.5f * head * uy, b.y - head * uy - 0.5f * head * ux),
                          ImVec2(b.x - head * ux - 0.5f * head * uy, b.y - head * uy + 0.5f * head * ux), color);
}

struct ShadedTriangle {
  double depth;
  ImVec2 a, b, c;
  ImU32 color;
};

void AddMesh(std::vector<ShadedTriangle>& out, const Projector& p, const DrawMesh& mesh, const Eigen::Isometry3d& X,
             const Eigen::Vector3d& base_rgb) {
  const Eigen::Vector3d light = (-p.forward + 0.5 * p.up).normalized();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = X * mesh.vertices[t[0]], b = X * mesh.vertices[t[1]], c = X * mesh.vertices[t[2]];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-15) continue;
    n.normalize();
    if (n.dot(p.forward) > 0) continue;  // back face
    ShadedTriangle s;
    double da, db, dc;
    if (!p.Project(a, s.a, &da) || !p.Project(b, s.b, &db) || !p.Project(c, s.c, &dc)) continue;
    s.depth = (da + db + dc) / 3;
    const double shade = 0.35 + 0.65 * std::max(0.0, n.dot(light));
    const Eigen::Vector3d rgb = (shade * base_rgb).cwiseMin(1.0);
    s.color = IM_COL32(static_cast<int>(255 * rgb.x()), static_cast<int>(255 * rgb.y()),
                       static_cast<int>(255 * rgb.z()), 255);
    out.push_back(s);
  }
}

// The slice's edges as one image over their bounding box within the view, blended over the panel's background.
void DrawSliceImage(const Projector& p, ImVec2 origin, ImVec2 size, const RobotScene& scene,
                    RobotViewBatches& batches) {
  std::vector<ImVec2>& ends = batches.scratch;
  ends.clear();
  ImVec2 lo(origin.x + size.x, origin.y + size.y), hi = origin;
  for (const auto& edge : scene.slice_edges_F) {
    ImVec2 sa, sb;
    if (!p.Project(edge[0], sa) || !p.Project(edge[1], sb)) continue;
    ends.push_back(sa);
    ends.push_back(sb);
    for (const ImVec2& e : {sa, sb}) {
      lo = ImVec2(std::min(lo.x, e.x), std::min(lo.y, e.y));
      hi = ImVec2(std::max(hi.x, e.x + 1), std::max(hi.y, e.y + 1));
    }
  }
  // Within the view only (the image's size is bounded by the view's).
  lo = ImVec2(std::max(lo.x, origin.x), std::max(lo.y, origin.y));
  hi = ImVec2(std::min(hi.x, origin.x + size.x), std::min(hi.y, origin.y + size.y));
  batches.slice.Reset(lo, hi.x > lo.x && hi.y > lo.y ? hi : lo, kPanelBackground);
  for (std::size_t i = 0; i + 1 < ends.size(); i += 2)
    batches.slice.AddLine(ends[i], ends[i + 1], IM_COL32(90, 200, 255, 60));
}

}  // namespace

DrawMesh ReduceForDrawing(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<std::array<int, 3>>& triangles, std::size_t max_triangles) {
  if (triangles.size() <= max_triangles || vertices.empty()) return {vertices, triangles};
  // Vertex clustering: the vertices of each cell of a grid merge into their centroid, the triangles that collapse
  // vanish; the cell grows until the budget is met. Unlike keeping every k-th triangle, the surface stays closed
  // (no holes to see through), at the price of detail.
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& v : vertices) box.extend(v);
  double cell = std::max(1e-6, box.diagonal().norm() / 200);
  DrawMesh mesh;
  for (int attempt = 0; attempt < 64; ++attempt, cell *= 1.2) {
    std::unordered_map<std::int64_t, int> cluster_of_cell;
    std::vector<int> cluster(vertices.size());
    std::vector<Eigen::Vector3d> sum;
    std::vector<int> count;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const Eigen::Vector3d c = ((vertices[i] - box.min()) / cell).array().floor();
      const std::int64_t key = (static_cast<std::int64_t>(c.x()) * 4096 + static_cast<std::int64_t>(c.y())) * 4096 +
                               static_cast<std::int64_t>(c.z());  // < 4096 cells per axis: at most 200 here
      const auto [it, added] = cluster_of_cell.emplace(key, static_cast<int>(sum.size()));
      if (added) {
        sum.push_back(Eigen::Vector3d::Zero());
        count.push_back(0);
      }
      cluster[i] = it->second;
      sum[it->second] += vertices[i];
      ++count[it->second];
    }
    mesh.vertices.resize(sum.size());
    for (std::size_t k = 0; k < sum.size(); ++k) mesh.vertices[k] = sum[k] / count[k];
    mesh.triangles.clear();
    std::set<std::array<int, 3>> seen;
    for (const auto& t : triangles) {
      std::array<int, 3> r{cluster[t[0]], cluster[t[1]], cluster[t[2]]};  // the winding is kept
      if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
      std::array<int, 3> key = r;
      std::sort(key.begin(), key.end());
      if (seen.insert(key).second) mesh.triangles.push_back(r);
    }
    if (mesh.triangles.size() <= max_triangles) break;
  }
  return mesh;
}

std::vector<std::array<Eigen::Vector3d, 2>> MeshEdges(const std::vector<Eigen::Vector3d>& vertices,
                                                      const std::vector<Eigen::Vector3i>& triangles,
                                                      std::size_t max_edges) {
  std::map<std::pair<int, int>, bool> seen;
  std::vector<std::array<Eigen::Vector3d, 2>> edges;
  for (const Eigen::Vector3i& t : triangles) {
    for (int e = 0; e < 3; ++e) {
      const int a = t[e], b = t[(e + 1) % 3];
      if (!seen.emplace(std::minmax(a, b), true).second) continue;
      edges.push_back({vertices[a], vertices[b]});
    }
  }
  if (edges.size() > max_edges) {
    const std::size_t stride = (edges.size() + max_edges - 1) / max_edges;
    std::vector<std::array<Eigen::Vector3d, 2>> kept;
    for (std::size_t i = 0; i < edges.size(); i += stride) kept.push_back(edges[i]);
    edges.swap(kept);
  }
  return edges;
}

void DrawRobotView(ImDrawList* draw, DirectRenderer& gl, RobotViewBatches& batches, ImVec2 origin, ImVec2 size,
                   const panel::Camera& camera, const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                   const Eigen::Isometry3d& X_FM_commanded, const RobotScene& scene, const panel::HandWrench& wrench) {
  draw->PushClipRect(origin, ImVec2(origin.x + size.x, origin.y + size.y), true);
  const Eigen::Vector3d target(0, 0, 0.5 * model.geometry().X_FM_home.translation().z());
  const Projector p = MakeProjector(origin, size, camera, target);

  // The workspace boundary slice around the ring (positions P can reach at the current orientation).
  // Thin, faint and many: 1 px lines without anti-aliasing, rasterised into one image over their bounding box
  // (line_image.h), blended there over the panel's background, and drawn as one opaque quad (so first: it covers
  // what was drawn before it in its box).
  const RobotViewBatches::SliceKey key{scene.slice_generation, camera.azimuth_deg, camera.elevation_deg,
                                       camera.distance_mm, origin.x, origin.y, size.x, size.y};
  if (batches.slice_drawn && key == batches.slice_key) {
    batches.slice_texture.Redraw(draw, gl);  // the same picture as the last frame's
  } else {
    DrawSliceImage(p, origin, size, scene, batches);
    batches.slice_texture.Draw(draw, gl, batches.slice);
    batches.slice_key = key;
    batches.slice_drawn = true;
  }

  // The frame F.
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  Line(draw, p, o, Eigen::Vector3d(0.08, 0, 0), IM_COL32(230, 80, 80, 255), 2);
  Line(draw, p, o, Eigen::Vector3d(0, 0.08, 0), IM_COL32(80, 230, 80, 255), 2);
  Line(draw, p, o, Eigen::Vector3d(0, 0, 0.08), IM_COL32(80, 120, 255, 255), 2);

  // Bone fragments, painter's order.
  std::vector<ShadedTriangle> triangles;
  triangles.reserve(scene.proximal_F.triangles.size() + scene.distal_M.triangles.size());
  AddMesh(triangles, p, scene.proximal_F, Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.95, 0.90, 0.78));
  AddMesh(triangles, p, scene.distal_M, X_FM, Eigen::Vector3d(0.95, 0.82, 0.70));
  std::sort(triangles.begin(), triangles.end(),
            [](const ShadedTriangle& a, const ShadedTriangle& b) { return a.depth > b.depth; });
  // Opaque GL triangles without anti-aliased edges (a closed mesh hides the edges anyway; direct_draw.h).
  batches.bone.Clear();
  for (const ShadedTriangle& t : triangles) batches.bone.AddTriangle(t.a, t.b, t.c, t.color);
  gl.Submit(draw, batches.bone);

  // Rings and arms.
  const double radius_fixed = model.p_FA(0).head<2>().norm();
  const double radius_moving = model.p_MB(0).head<2>().norm();
  Ring(draw, p, Eigen::Isometry3d::Identity(), radius_fixed, IM_COL32(170, 170, 185, 255));
  Ring(draw, p, X_FM, radius_moving, IM_COL32(240, 190, 60, 255));
  for (int i = 0; i < robot::kNumArms; ++i) {
    const Eigen::Vector3d a = model.p_FA(i), b = X_FM * model.p_MB(i);
    Line(draw, p, a, b, IM_COL32(120, 220, 140, 255), 6.0f);
    ImVec2 sa, sb;
    if (p.Project(a, sa)) draw->AddCircleFilled(sa, 7, IM_COL32(220, 220, 230, 255));
    if (p.Project(b, sb)) draw->AddCircleFilled(sb, 6, IM_COL32(255, 120, 80, 255));
  }
  // The commanded ring centre (a cross) against the measured one.
  ImVec2 sc;
  if (p.Project(X_FM_commanded.translation(), sc)) {
    draw->AddLine(ImVec2(sc.x - 8, sc.y), ImVec2(sc.x + 8, sc.y), IM_COL32(255, 255, 255, 200), 2);
    draw->AddLine(ImVec2(sc.x, sc.y - 8), ImVec2(sc.x, sc.y + 8), IM_COL32(255, 255, 255, 200), 2);
  }
  // Force and torque on the hand, drawn at P.
  const Eigen::Vector3d P = X_FM.translation();
  Arrow(draw, p, P, kForceArrowMPerN * Eigen::Vector3d(wrench.force_n[0], wrench.force_n[1], wrench.force_n[2]),
        IM_COL32(255, 70, 70, 255));
  Arrow(draw, p, P,
        kTorqueArrowMPerNm * Eigen::Vector3d(wrench.torque_nm[0], wrench.torque_nm[1], wrench.torque_nm[2]),
        IM_COL32(200, 90, 255, 255));
  draw->PopClipRect();
}

}  // namespace robossis::apps
