// Mesh statistics and binary STL/PLY files.

#include "geometry/triangle_mesh.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "src/core/files.h"

namespace robossis::geometry {

namespace {

template <typename T>
void Append(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the project targets little-endian x86-64/arm64
  out.append(bytes, sizeof(T));
}

}  // namespace

MeshStatistics ComputeMeshStatistics(const TriangleMesh& mesh) {
  MeshStatistics s;
  s.triangles = mesh.triangles.size();
  s.vertices = mesh.vertices.size();
  if (!mesh.vertices.empty()) {
    s.min = s.max = mesh.vertices.front();
    for (const Eigen::Vector3d& v : mesh.vertices) {
      s.min = s.min.cwiseMin(v);
      s.max = s.max.cwiseMax(v);
    }
  }
  if (mesh.triangles.empty()) return s;
  const int n = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if ((t.array() < 0).any() || (t.array() >= n).any()) return s;  // invalid index: nothing below holds
  }
  s.volume = SignedVolume(mesh);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    if ((b - a).cross(c - a).squaredNorm() == 0.0) ++s.degenerate_triangles;
  }
  // A closed, consistently oriented 2-manifold has each directed edge exactly once and its reverse exactly once.
  const DirectedEdges edges(mesh);
  bool watertight = true, oriented = true;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int count = edges.Count(t[k], t[(k + 1) % 3]), reverse_count = edges.Count(t[(k + 1) % 3], t[k]);
      if (count + reverse_count != 2) watertight = false;
      if (count != 1 || reverse_count != 1) oriented = false;
    }
  }
  s.watertight = watertight;
  s.consistently_oriented = oriented;
  s.outward = oriented && s.volume > 0;
  return s;
}

DirectedEdges::DirectedEdges(const TriangleMesh& mesh) : row_start_(mesh.vertices.size() + 1, 0) {
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++row_start_[t[k] + 1];
  }
  for (std::size_t v = 1; v < row_start_.size(); ++v) row_start_[v] += row_start_[v - 1];
  to_.resize(3 * mesh.triangles.size());
  triangle_.resize(3 * mesh.triangles.size());
  std::vector<int> fill(row_start_.begin(), row_start_.end() - 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int slot = fill[mesh.triangles[t][k]]++;
      to_[slot] = mesh.triangles[t][(k + 1) % 3];
      triangle_[slot] = static_cast<int>(t);
    }
  }
}

int DirectedEdges::Count(int from, int to) const noexcept {
  int count = 0;
  for (int i = row_start_[from]; i < row_start_[from + 1]; ++i) count += to_[i] == to ? 1 : 0;
  return count;
}

int DirectedEdges::Owner(int from, int to) const noexcept {
  for (int i = row_start_[from]; i < row_start_[from + 1]; ++i) {
    if (to_[i] == to) return triangle_[i];
  }
  return -1;
}

double SignedVolume(const TriangleMesh& mesh) {
  if (mesh.vertices.empty()) return 0;
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);  // reduces round-off in the sum
  double six_volume = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]] - centre, b = mesh.vertices[t[1]] - centre,
                          c = mesh.vertices[t[2]] - centre;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

void FlipOrientation(TriangleMesh& mesh) {
  for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);
}

std::string BinaryStlBytes(const TriangleMesh& mesh, double file_scale) {
  std::string out;
  out.reserve(84 + 50 * mesh.triangles.size());
  std::string header = "robossis workspace boundary (binary STL)";
  header.resize(80, ' ');
  out += header;
  Append<std::uint32_t>(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]] * file_scale, b = mesh.vertices[t[1]] * file_scale,
                          c = mesh.vertices[t[2]] * file_scale;
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double norm = normal.norm();
    normal = norm > 0 ? Eigen::Vector3d(normal / norm) : Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d* v : std::array<const Eigen::Vector3d*, 4>{&normal, &a, &b, &c}) {
      for (int k = 0; k < 3; ++k) Append<float>(out, static_cast<float>((*v)[k]));
    }
    Append<std::uint16_t>(out, 0);
  }
  return out;
}

std::string BinaryPlyBytes(const TriangleMesh& mesh, double file_scale) {
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment robossis workspace boundary\n"
         << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
         << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  std::string out = header.str();
  out.reserve(out.size() + 12 * mesh.vertices.size() + 13 * mesh.triangles.size());
  for (const Eigen::Vector3d& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) Append<float>(out, static_cast<float>(v[k] * file_scale));
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    Append<std::uint8_t>(out, 3);
    for (int k = 0; k < 3; ++k) Append<std::int32_t>(out, t[k]);
  }
  return out;
}

void WriteBinaryStl(const TriangleMesh& mesh, double file_scale, const std::filesystem::path& file) {
  WriteFileAtomically(file, BinaryStlBytes(mesh, file_scale));
}

void WriteBinaryPly(const TriangleMesh& mesh, double file_scale, const std::filesystem::path& file) {
  WriteFileAtomically(file, BinaryPlyBytes(mesh, file_scale));
}

TriangleMesh ParseBinaryPly(const std::string& bytes, double file_scale, const std::string& name) {
  auto fail = [&](const std::string& what) { throw std::runtime_error(name + ": " + what); };
  const std::string end_marker = "end_header\n";
  const std::size_t end = bytes.find(end_marker);
  if (bytes.rfind("ply\n", 0) != 0 || end == std::string::npos) fail("not a PLY file (missing 'ply' or 'end_header')");
  std::istringstream header(bytes.substr(0, end));
  std::string line;
  long long n_vertices = -1, n_faces = -1;
  bool binary_le = false;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string w0, w1;
    words >> w0 >> w1;
    if (w0 == "format") binary_le = (w1 == "binary_little_endian");
    if (w0 == "element" && (w1 == "vertex" || w1 == "face")) {
      long long& count = w1 == "vertex" ? n_vertices : n_faces;
      if (count >= 0) fail("'element " + w1 + "' appears twice in the header");
      if (!(words >> count) || count < 0) fail("'" + line + "': expected a count from 0 to " + std::to_string(LLONG_MAX));
    }
  }
  if (!binary_le) fail("expected 'format binary_little_endian 1.0' (the layout WriteBinaryPly writes)");
  if (n_vertices < 0 || n_faces < 0) fail("header lacks 'element vertex N' or 'element face N'");
  // 12 bytes a vertex, 13 a triangle. The counts are bounded by the body's size before they are multiplied: a count
  // near 2^63 would wrap the product to a size that matches.
  const std::size_t body = end + end_marker.size();
  const std::size_t body_bytes = bytes.size() - body;
  const auto vertices = static_cast<unsigned long long>(n_vertices), faces = static_cast<unsigned long long>(n_faces);
  if (vertices > body_bytes / 12 || faces > body_bytes / 13 || body_bytes != 12 * vertices + 13 * faces) {
    fail(std::to_string(body_bytes) + " bytes after the header; expected 12 per vertex and 13 per triangle for " +
         std::to_string(n_vertices) + " vertices and " + std::to_string(n_faces) + " triangles (truncated?)");
  }
  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<std::size_t>(n_vertices));
  mesh.triangles.resize(static_cast<std::size_t>(n_faces));
  const char* p = bytes.data() + body;
  for (Eigen::Vector3d& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k, p += 4) {
      float f;
      std::memcpy(&f, p, 4);
      if (!std::isfinite(f)) fail("non-finite vertex coordinate");
      v[k] = static_cast<double>(f) / file_scale;
    }
  }
  for (Eigen::Vector3i& t : mesh.triangles) {
    if (static_cast<unsigned char>(*p) != 3) fail("a face is not a triangle");
    ++p;
    for (int k = 0; k < 3; ++k, p += 4) {
      std::int32_t index;
      std::memcpy(&index, p, 4);
      if (index < 0 || index >= n_vertices) fail("vertex index " + std::to_string(index) + " out of range");
      t[k] = index;
    }
  }
  return mesh;
}

TriangleMesh ReadBinaryPly(const std::filesystem::path& file, double file_scale) {
  return ParseBinaryPly(ReadTextFile(file), file_scale, file.string());
}

}  // namespace robossis::geometry
