#include "robot/sim/bone_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "src/core/files.h"

namespace robossis::sim {

void TriangleMesh::Transform(const Eigen::Isometry3d& X) {
  for (Eigen::Vector3d& v : vertices) v = X * v;
  if (X.linear().determinant() < 0) {
    for (auto& t : triangles) std::swap(t[1], t[2]);
  }
}

namespace {

class Welder {
 public:
  explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
  int Add(const Eigen::Vector3d& p) {
    const auto key = std::make_tuple(p.x(), p.y(), p.z());
    const auto [it, inserted] = index_.emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p);
    return it->second;
  }
  void AddTriangle(const std::array<Eigen::Vector3d, 3>& p) {
    std::array<int, 3> t{Add(p[0]), Add(p[1]), Add(p[2])};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) mesh_.triangles.push_back(t);
  }

 private:
  TriangleMesh& mesh_;
  std::map<std::tuple<double, double, double>, int> index_;
};

TriangleMesh ReadBinaryStl(const std::string& bytes, const std::string& name) {
  if (bytes.size() < 84) throw std::runtime_error(name + ": binary STL shorter than its header");
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() < 84 + 50ull * count) throw std::runtime_error(name + ": binary STL truncated");
  TriangleMesh mesh;
  Welder welder(mesh);
  for (std::uint32_t f = 0; f < count; ++f) {
    const char* rec = bytes.data() + 84 + 50ull * f;
    std::array<Eigen::Vector3d, 3> p;
    for (int v = 0; v < 3; ++v) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 + 12 * v, 12);
      p[v] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      // A NaN coordinate would break the welder's ordering of vertices (and every mass property after it).
      if (!p[v].allFinite()) {
        throw std::runtime_error(name + ": binary STL facet " + std::to_string(f + 1) + " vertex " +
                                 std::to_string(v + 1) + ": expected three finite coordinates");
      }
    }
    welder.AddTriangle(p);
  }
  return mesh;
}

}  // namespace

TriangleMesh ReadStl(const std::filesystem::path& file) {
  const std::string bytes = ReadBoundedFile(file, kMaxStlFileBytes, "STL mesh");
  const bool ascii = bytes.compare(0, 5, "solid") == 0 && bytes.find("facet") != std::string::npos;
  TriangleMesh mesh;
  if (!ascii) {
    mesh = ReadBinaryStl(bytes, file.string());
  } else {
    Welder welder(mesh);
    std::istringstream lines(bytes);
    std::string line;
    std::array<Eigen::Vector3d, 3> p;
    int n = 0, line_no = 0;
    while (std::getline(lines, line)) {
      ++line_no;
      std::istringstream ls(line);
      std::string word;
      ls >> word;
      if (word == "vertex") {
        double x, y, z;
        if (!(ls >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
          throw std::runtime_error(file.string() + " line " + std::to_string(line_no) +
                                   ": expected 'vertex X Y Z' with three finite numbers");
        }
        if (n >= 3) throw std::runtime_error(file.string() + " line " + std::to_string(line_no) + ": facet with more than 3 vertices");
        p[n++] = Eigen::Vector3d(x, y, z);
      } else if (word == "endloop") {
        if (n != 3) throw std::runtime_error(file.string() + " line " + std::to_string(line_no) + ": facet without 3 vertices");
        welder.AddTriangle(p);
        n = 0;
      }
    }
  }
  if (mesh.triangles.empty()) throw std::runtime_error(file.string() + ": STL holds no triangles");
  return mesh;
}

std::string StlAscii(const TriangleMesh& mesh, const std::string& header) {
  std::ostringstream os;
  os.precision(9);
  os << "solid " << header << "\n";
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() > 0) n.normalize();
    os << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n outer loop\n";
    for (const Eigen::Vector3d* v : {&a, &b, &c}) os << "  vertex " << v->x() << " " << v->y() << " " << v->z() << "\n";
    os << " endloop\nendfacet\n";
  }
  os << "endsolid\n";
  return os.str();
}

MassProperties CalcMassProperties(const TriangleMesh& mesh) {
  // Signed tetrahedra (origin, a, b, c): volume, first and second moments (covariance integrals).
  double vol = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T dV
  const Eigen::Matrix3d canonical = (Eigen::Matrix3d() << 2, 1, 1, 1, 2, 1, 1, 1, 2).finished() / 120.0;
  // Reference point near the mesh keeps the sums well conditioned.
  const Eigen::Vector3d o = mesh.vertices.front();
  for (const auto& t : mesh.triangles) {
    Eigen::Matrix3d A;
    A.col(0) = mesh.vertices[t[0]] - o;
    A.col(1) = mesh.vertices[t[1]] - o;
    A.col(2) = mesh.vertices[t[2]] - o;
    const double det = A.determinant();
    vol += det / 6.0;
    first += det / 24.0 * (A.col(0) + A.col(1) + A.col(2));
    second += det * A * canonical * A.transpose();
  }
  MassProperties mp;
  mp.volume_m3 = vol;
  const Eigen::Vector3d c = first / vol;
  const Eigen::Matrix3d cov = second - vol * c * c.transpose();  // about the centroid
  mp.centroid = c + o;
  mp.inertia_per_density = cov.trace() * Eigen::Matrix3d::Identity() - cov;
  return mp;
}

namespace {

// A convex polygon (a triangle) clipped to the half-space sign * (z - z0) >= 0 (Sutherland–Hodgman).
std::vector<Eigen::Vector3d> ClipZ(const std::vector<Eigen::Vector3d>& poly, double z0, double sign) {
  std::vector<Eigen::Vector3d> out;
  const std::size_t n = poly.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d& a = poly[k];
    const Eigen::Vector3d& b = poly[(k + 1) % n];
    const double da = sign * (a.z() - z0), db = sign * (b.z() - z0);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

}  // namespace

CutMesh CutMeshAtZ(const TriangleMesh& mesh, double z_cut) {
  // No vertex exactly on the plane: nudge the plane by a negligible amount if one is (keeps every cut strict).
  for (int attempt = 0; attempt < 100; ++attempt) {
    bool on_plane = false;
    for (const Eigen::Vector3d& v : mesh.vertices) on_plane = on_plane || std::abs(v.z() - z_cut) < 1e-12;
    if (!on_plane) break;
    z_cut += 1e-9;
  }
  CutMesh out;
  std::vector<int> map_below(mesh.vertices.size(), -1), map_above(mesh.vertices.size(), -1);
  auto vertex_of = [&](TriangleMesh& m, std::vector<int>& map, int v) {
    if (map[v] < 0) {
      map[v] = static_cast<int>(m.vertices.size());
      m.vertices.push_back(mesh.vertices[v]);
    }
    return map[v];
  };
  // Cut points are keyed by their edge so both sides and both neighbouring triangles share them.
  struct CutPoint { int below = -1, above = -1; Eigen::Vector3d p; };
  std::map<std::pair<int, int>, int> cut_index;
  std::vector<CutPoint> cut_points;
  auto cut_point_of = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = cut_index.find(key);
    if (it != cut_index.end()) return it->second;
    const Eigen::Vector3d& pa = mesh.vertices[key.first];
    const Eigen::Vector3d& pb = mesh.vertices[key.second];
    CutPoint cp;
    cp.p = pa + (pb - pa) * ((z_cut - pa.z()) / (pb.z() - pa.z()));
    cp.p.z() = z_cut;
    cp.below = static_cast<int>(out.below.vertices.size());
    out.below.vertices.push_back(cp.p);
    cp.above = static_cast<int>(out.above.vertices.size());
    out.above.vertices.push_back(cp.p);
    cut_points.push_back(cp);
    const int id = static_cast<int>(cut_points.size()) - 1;
    cut_index.emplace(key, id);
    return id;
  };
  std::vector<std::pair<int, int>> segments;  // cut-point ids
  for (const auto& t : mesh.triangles) {
    std::array<bool, 3> up{};
    for (int k = 0; k < 3; ++k) up[k] = mesh.vertices[t[k]].z() > z_cut;
    if (up[0] == up[1] && up[1] == up[2]) {
      TriangleMesh& m = up[0] ? out.above : out.below;
      std::vector<int>& map = up[0] ? map_above : map_below;
      m.triangles.push_back({vertex_of(m, map, t[0]), vertex_of(m, map, t[1]), vertex_of(m, map, t[2])});
      continue;
    }
    // Walk the triangle's edges in order; each side gets a convex polygon (ids in its own mesh), fanned.
    std::vector<int> poly_below, poly_above;
    std::array<int, 2> seg{};
    int nseg = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      (up[k] ? poly_above : poly_below).push_back(up[k] ? vertex_of(out.above, map_above, a)
                                                        : vertex_of(out.below, map_below, a));
      if (up[k] != up[(k + 1) % 3]) {
        const int id = cut_point_of(a, b);
        poly_below.push_back(cut_points[id].below);
        poly_above.push_back(cut_points[id].above);
        seg[nseg++] = id;
      }
    }
    segments.emplace_back(seg[0], seg[1]);
    for (std::size_t k = 1; k + 1 < poly_below.size(); ++k) {
      out.below.triangles.push_back({poly_below[0], poly_below[k], poly_below[k + 1]});
    }
    for (std::size_t k = 1; k + 1 < poly_above.size(); ++k) {
      out.above.triangles.push_back({poly_above[0], poly_above[k], poly_above[k + 1]});
    }
  }
  if (segments.empty()) throw std::invalid_argument("mesh cut: the plane z = " + std::to_string(z_cut) + " misses the mesh");
  // Chain the segments into closed loops (every cut point of a closed manifold has exactly two segments).
  std::vector<std::array<int, 2>> adj(cut_points.size(), {-1, -1});
  for (int s = 0; s < static_cast<int>(segments.size()); ++s) {
    for (int end : {segments[s].first, segments[s].second}) {
      auto& slot = adj[end];
      if (slot[0] < 0) slot[0] = s;
      else if (slot[1] < 0) slot[1] = s;
      else throw std::invalid_argument("mesh cut: non-manifold edge on the cut plane");
    }
  }
  std::vector<bool> used(segments.size(), false);
  double largest = -1;
  for (int s0 = 0; s0 < static_cast<int>(segments.size()); ++s0) {
    if (used[s0]) continue;
    std::vector<int> loop;
    int s = s0, p = segments[s0].first;
    while (!used[s]) {
      used[s] = true;
      loop.push_back(p);
      p = segments[s].first == p ? segments[s].second : segments[s].first;
      const auto& a = adj[p];
      if (a[0] < 0 || a[1] < 0) throw std::invalid_argument("mesh cut: the mesh is open on the cut plane");
      s = a[0] == s ? a[1] : a[0];
    }
    ++out.loops;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int id : loop) c += cut_points[id].p;
    c /= static_cast<double>(loop.size());
    const int cb = static_cast<int>(out.below.vertices.size());
    out.below.vertices.push_back(c);
    const int ca = static_cast<int>(out.above.vertices.size());
    out.above.vertices.push_back(c);
    double area = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const CutPoint& p0 = cut_points[loop[k]];
      const CutPoint& p1 = cut_points[loop[(k + 1) % loop.size()]];
      const double z = (p0.p - c).cross(p1.p - c).z();
      area += 0.5 * z;
      // Cap of the lower part faces +z, cap of the upper part faces -z.
      if (z >= 0) {
        out.below.triangles.push_back({cb, p0.below, p1.below});
        out.above.triangles.push_back({ca, p1.above, p0.above});
      } else {
        out.below.triangles.push_back({cb, p1.below, p0.below});
        out.above.triangles.push_back({ca, p0.above, p1.above});
      }
    }
    if (std::abs(area) > largest) {
      largest = std::abs(area);
      out.cap_centroid = c;
    }
  }
  return out;
}

std::vector<std::vector<Eigen::Vector3d>> SlabPointSets(const TriangleMesh& mesh, double z_from, double z_to,
                                                        double slab_height) {
  std::vector<std::vector<Eigen::Vector3d>> sets;
  const int n = std::max(1, static_cast<int>(std::ceil((z_to - z_from) / slab_height - 1e-9)));
  const double h = (z_to - z_from) / n;
  for (int s = 0; s < n; ++s) {
    const double z0 = z_from + s * h, z1 = z0 + h;
    std::vector<Eigen::Vector3d> pts;
    for (const auto& t : mesh.triangles) {
      const double zmin = std::min({mesh.vertices[t[0]].z(), mesh.vertices[t[1]].z(), mesh.vertices[t[2]].z()});
      const double zmax = std::max({mesh.vertices[t[0]].z(), mesh.vertices[t[1]].z(), mesh.vertices[t[2]].z()});
      if (zmax < z0 || zmin > z1) continue;
      std::vector<Eigen::Vector3d> poly{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
      poly = ClipZ(ClipZ(poly, z0, +1), z1, -1);
      pts.insert(pts.end(), poly.begin(), poly.end());
    }
    if (pts.size() >= 4) sets.push_back(std::move(pts));
  }
  return sets;
}

}  // namespace robossis::sim
