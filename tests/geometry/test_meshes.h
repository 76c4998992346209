#pragma once
// Small closed meshes with known geometry for the geometry tests.

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace robossis::geometry::testing {

// Distance from p to the triangle (a, b, c), computed differently from the library (which walks Voronoi regions):
// the projection onto the plane if it falls inside the triangle, else the nearest of the three edges.
inline double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  auto segment = [&p](const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
    const double t = std::clamp((p - s).dot(e - s) / (e - s).squaredNorm(), 0.0, 1.0);
    return (p - (s + t * (e - s))).norm();
  };
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d x = p - n.dot(p - a) * n;  // projection onto the plane
  const bool inside = n.dot((b - a).cross(x - a)) >= 0 && n.dot((c - b).cross(x - b)) >= 0 &&
                      n.dot((a - c).cross(x - c)) >= 0;
  if (inside) return std::abs(n.dot(p - a));
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

// Axis-aligned box [lo, hi], outward oriented (12 triangles).
inline TriangleMesh BoxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

// Unit-radius icosphere refined `levels` times (vertices on the sphere), outward oriented.
inline TriangleMesh IcoSphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& v : m.vertices) v.normalize();
  for (int l = 0; l < levels; ++l) {
    std::vector<Eigen::Vector3i> next;
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return mid[key] = static_cast<int>(m.vertices.size()) - 1;
    };
    for (const auto& tri : m.triangles) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      next.emplace_back(tri[0], a, c);
      next.emplace_back(tri[1], b, a);
      next.emplace_back(tri[2], c, b);
      next.emplace_back(a, b, c);
    }
    m.triangles = next;
  }
  for (auto& v : m.vertices) v *= radius;
  return m;
}

}  // namespace robossis::geometry::testing
