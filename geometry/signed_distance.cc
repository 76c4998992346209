// Nearest triangle through FCL's bounding-volume tree + angle-weighted pseudonormal sign (Baerentzen & Aanaes 2005).

#include "geometry/signed_distance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>

namespace robossis::geometry {

namespace {

// Where on a triangle the closest point lies: the feature whose pseudonormal gives the sign.
enum class Feature { kFace, kEdge01, kEdge12, kEdge20, kVertex0, kVertex1, kVertex2 };

// Closest point on triangle (a, b, c) to p, with its feature (Ericson, Real-Time Collision Detection, §5.1.5).
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c, Feature* feature) noexcept {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) { *feature = Feature::kVertex0; return a; }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) { *feature = Feature::kVertex1; return b; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    *feature = Feature::kEdge01;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) { *feature = Feature::kVertex2; return c; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    *feature = Feature::kEdge20;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    *feature = Feature::kEdge12;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  *feature = Feature::kFace;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double AngleAt(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const Eigen::Vector3d u = q - p, v = r - p;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

struct BoundaryDistanceField::Impl {
  std::shared_ptr<fcl::BVHModel<fcl::AABBd>> bvh;  // FCL builds and fits the tree; we traverse it
  std::vector<Eigen::Vector3d> face_normal;                 // unit, outward
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normal;  // per triangle: edges 01, 12, 20 (unit pseudonormals)
  std::vector<Eigen::Vector3d> vertex_normal;               // angle-weighted, unit
};

namespace {
std::atomic<std::uint64_t> next_field_id{0};
}  // namespace

const char* ToString(QueryStatus status) {
  switch (status) {
    case QueryStatus::kOk: return "ok";
    case QueryStatus::kNoField: return "no_field";
    case QueryStatus::kNonFinite: return "non_finite";
    case QueryStatus::kFclFailure: return "fcl_failure";
    case QueryStatus::kOffGrid: return "off_grid";
  }
  return "unknown";
}

BoundaryDistanceField::BoundaryDistanceField(TriangleMesh mesh)
    : BoundaryDistanceField(std::move(mesh), MeshStatistics{}) {}

BoundaryDistanceField::BoundaryDistanceField(TriangleMesh mesh, const MeshStatistics& stats)
    : mesh_(std::move(mesh)), stats_(stats), id_(next_field_id.fetch_add(1) + 1), impl_(new Impl) {
  if (stats_.triangles != mesh_.triangles.size() || stats_.vertices != mesh_.vertices.size()) {
    stats_ = ComputeMeshStatistics(mesh_);  // not given (or not this mesh's)
  }
  if (mesh_.triangles.empty()) throw std::invalid_argument("boundary mesh is empty");
  if (!stats_.watertight || !stats_.consistently_oriented) {
    throw std::invalid_argument("boundary mesh is not a closed, consistently oriented surface (watertight=" +
                                std::to_string(stats_.watertight) + ", oriented=" +
                                std::to_string(stats_.consistently_oriented) + "): its signed distance is undefined");
  }
  if (stats_.volume < 0) {
    FlipOrientation(mesh_);
    stats_ = ComputeMeshStatistics(mesh_);
  }
  const auto& V = mesh_.vertices;
  const auto& T = mesh_.triangles;
  Impl& m = *impl_;
  m.face_normal.resize(T.size());
  m.edge_normal.resize(T.size());
  m.vertex_normal.assign(V.size(), Eigen::Vector3d::Zero());
  for (std::size_t t = 0; t < T.size(); ++t) {
    const Eigen::Vector3d &a = V[T[t][0]], &b = V[T[t][1]], &c = V[T[t][2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    m.face_normal[t] = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    // Angle-weighted vertex pseudonormals (a degenerate face has zero normal and adds nothing).
    m.vertex_normal[T[t][0]] += AngleAt(a, b, c) * m.face_normal[t];
    m.vertex_normal[T[t][1]] += AngleAt(b, c, a) * m.face_normal[t];
    m.vertex_normal[T[t][2]] += AngleAt(c, a, b) * m.face_normal[t];
  }
  for (Eigen::Vector3d& n : m.vertex_normal) n.normalize();
  // In a closed oriented mesh the reverse of a triangle's edge (i, j) belongs to its neighbour across that edge.
  const DirectedEdges edges(mesh_);
  for (std::size_t t = 0; t < T.size(); ++t) {
    for (int e = 0; e < 3; ++e) {
      // Edge pseudonormal: the sum of the two adjacent faces' normals (the neighbour owns the reversed edge).
      const int neighbour = edges.Owner(T[t][(e + 1) % 3], T[t][e]);
      m.edge_normal[t][e] = (m.face_normal[t] + m.face_normal[neighbour]).normalized();
    }
  }
  m.bvh = std::make_shared<fcl::BVHModel<fcl::AABBd>>();
  // Split at the box centre: the fastest build of FCL's three rules here (0.036 s vs 0.046 s mean, 0.074 s median for
  // 37k triangles) with the same query times; builds matter because live slices are rebuilt while the hand moves.
  m.bvh->bv_splitter.reset(new fcl::detail::BVSplitter<fcl::AABBd>(fcl::detail::SPLIT_METHOD_BV_CENTER));
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(T.size());
  for (const Eigen::Vector3i& t : T) triangles.emplace_back(t[0], t[1], t[2]);
  m.bvh->beginModel(static_cast<int>(T.size()), static_cast<int>(V.size()));
  m.bvh->addSubModel(V, triangles);
  m.bvh->endModel();
  // The search below reads the tree's boxes and its leaves' triangle ids (primitiveId), never FCL's own copies of the
  // vertices and triangles (mesh_ holds them): freed, about 24 of the field's 350 bytes per triangle (the atlas holds
  // some 2 million triangles). FCL's destructor deletes null arrays as a no-op.
  delete[] m.bvh->vertices;
  m.bvh->vertices = nullptr;
  delete[] m.bvh->tri_indices;
  m.bvh->tri_indices = nullptr;
}

BoundaryDistanceField::~BoundaryDistanceField() = default;

struct SignedDistanceQuery::State {
  // Warm start: the previous query's field and closest triangle. In a haptic loop the point moves little between
  // ticks, so the distance to the previous closest triangle is a tight upper bound that prunes most of the tree.
  std::uint64_t last_field_id = 0;  // 0: none
  int last_triangle = -1;
  // Inside cutoff (set_inside_cutoff): the last exact query point found inside, farther than the cutoff.
  double inside_cutoff = std::numeric_limits<double>::infinity();
  std::uint64_t anchor_field_id = 0;
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
  double anchor_distance = 0;
};

namespace {

// Squared distance from p to an axis-aligned box: a lower bound for everything inside it.
double SquaredDistanceToBox(const fcl::AABBd& box, const Eigen::Vector3d& p) noexcept {
  return (box.min_ - p).cwiseMax(p - box.max_).cwiseMax(0.0).squaredNorm();
}

// Branch-and-bound nearest-triangle search over FCL's tree: nearer child first, prune a subtree whose bound is not
// below the best distance so far. Exact (the leaves use the exact point-triangle distance), allocation-free; the
// recursion depth is the tree depth.
struct NearestTriangleSearch {
  const fcl::BVHModel<fcl::AABBd>& bvh;
  const TriangleMesh& mesh;
  const Eigen::Vector3d& q;
  double best_squared;
  int best_triangle;

  double SquaredDistanceToTriangle(int t) const noexcept {
    const Eigen::Vector3i& tri = mesh.triangles[static_cast<std::size_t>(t)];
    Feature unused;
    return (q - ClosestPointOnTriangle(q, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]],
                                       &unused)).squaredNorm();
  }

  void Visit(int node_id) noexcept {
    const fcl::BVNode<fcl::AABBd>& node = bvh.getBV(node_id);
    if (node.isLeaf()) {
      const int t = node.primitiveId();
      const double d2 = SquaredDistanceToTriangle(t);
      if (d2 < best_squared) {
        best_squared = d2;
        best_triangle = t;
      }
      return;
    }
    int near = node.leftChild(), far = node.rightChild();
    double near_bound = SquaredDistanceToBox(bvh.getBV(near).bv, q);
    double far_bound = SquaredDistanceToBox(bvh.getBV(far).bv, q);
    if (far_bound < near_bound) {
      std::swap(near, far);
      std::swap(near_bound, far_bound);
    }
    if (near_bound < best_squared) Visit(near);
    if (far_bound < best_squared) Visit(far);
  }
};

}  // namespace

SignedDistanceQuery::SignedDistanceQuery() : state_(new State) {}
SignedDistanceQuery::~SignedDistanceQuery() = default;
SignedDistanceQuery::SignedDistanceQuery(SignedDistanceQuery&&) noexcept = default;
SignedDistanceQuery& SignedDistanceQuery::operator=(SignedDistanceQuery&&) noexcept = default;

QueryStatus SignedDistanceQuery::Query(const BoundaryDistanceField* field, const Eigen::Vector3d& q, double radius,
                                       SignedDistanceResult* out) noexcept {
  *out = SignedDistanceResult{};
  if (field == nullptr) return out->status = QueryStatus::kNoField;
  if (!q.allFinite() || !std::isfinite(radius) || radius < 0) return out->status = QueryStatus::kNonFinite;
  State& s = *state_;
  if (s.anchor_field_id == field->id() && (q - s.anchor).norm() <= s.anchor_distance - s.inside_cutoff) {
    // The boundary is at least anchor_distance - |q - anchor| >= cutoff away and q cannot have crossed it.
    out->inside = true;
    out->beyond_inside_cutoff = true;
    out->signed_distance = s.inside_cutoff - radius;
    out->nearest = q;
    return out->status = QueryStatus::kOk;
  }
  const BoundaryDistanceField::Impl& m = field->impl();
  NearestTriangleSearch search{*m.bvh, field->mesh(), q, std::numeric_limits<double>::infinity(), -1};
  if (s.last_field_id == field->id() && s.last_triangle >= 0) {
    // Seed the search with the exact distance to the previous closest triangle: only bounding volumes that could
    // hold something closer are visited, and the answer is still the global minimum.
    search.best_triangle = s.last_triangle;
    search.best_squared = search.SquaredDistanceToTriangle(s.last_triangle);
  }
  if (SquaredDistanceToBox(m.bvh->getBV(0).bv, q) < search.best_squared) search.Visit(0);
  const int t = search.best_triangle;
  if (t < 0 || static_cast<std::size_t>(t) >= field->mesh().triangles.size()) {
    s.last_field_id = 0;
    return out->status = QueryStatus::kFclFailure;
  }
  s.last_field_id = field->id();
  s.last_triangle = t;
  const Eigen::Vector3i& tri = field->mesh().triangles[static_cast<std::size_t>(t)];
  const auto& V = field->mesh().vertices;
  Feature feature = Feature::kFace;
  const Eigen::Vector3d c = ClosestPointOnTriangle(q, V[tri[0]], V[tri[1]], V[tri[2]], &feature);
  Eigen::Vector3d pseudonormal = m.face_normal[t];
  switch (feature) {
    case Feature::kFace: break;
    case Feature::kEdge01: pseudonormal = m.edge_normal[t][0]; break;
    case Feature::kEdge12: pseudonormal = m.edge_normal[t][1]; break;
    case Feature::kEdge20: pseudonormal = m.edge_normal[t][2]; break;
    case Feature::kVertex0: pseudonormal = m.vertex_normal[tri[0]]; break;
    case Feature::kVertex1: pseudonormal = m.vertex_normal[tri[1]]; break;
    case Feature::kVertex2: pseudonormal = m.vertex_normal[tri[2]]; break;
  }
  const Eigen::Vector3d offset = q - c;
  const double distance = offset.norm();
  const bool inside = offset.dot(pseudonormal) <= 0;  // eq. (Baerentzen & Aanaes 2005, Theorem 1)
  out->inside = inside;
  out->signed_distance = (inside ? distance : -distance) - radius;
  out->nearest = c;
  out->triangle = static_cast<int>(t);
  // Outward normal: along the offset when it is resolvable, else the feature's pseudonormal.
  const double scale = 1e-12 * (1.0 + c.cwiseAbs().maxCoeff());
  out->normal = distance > scale ? Eigen::Vector3d((inside ? -offset : offset) / distance) : pseudonormal;
  if (inside && distance > s.inside_cutoff) {
    s.anchor_field_id = field->id();
    s.anchor = q;
    s.anchor_distance = distance;
  }
  return out->status = QueryStatus::kOk;
}

void SignedDistanceQuery::set_inside_cutoff(double cutoff) noexcept {
  state_->inside_cutoff = cutoff > 0 ? cutoff : std::numeric_limits<double>::infinity();
  state_->anchor_field_id = 0;
}

}  // namespace robossis::geometry
