// FCL unsigned distance + angle-weighted pseudonormal sign (Baerentzen & Aanaes 2005).

#include "geometry/signed_distance.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_shape_distance_traversal_node.h>
#include <fcl/narrowphase/distance.h>

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
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh;
  std::vector<Eigen::Vector3d> face_normal;                 // unit, outward
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normal;  // per triangle: edges 01, 12, 20 (unit pseudonormals)
  std::vector<Eigen::Vector3d> vertex_normal;               // angle-weighted, unit
};

const char* ToString(QueryStatus status) {
  switch (status) {
    case QueryStatus::kOk: return "ok";
    case QueryStatus::kNoField: return "no_field";
    case QueryStatus::kNonFinite: return "non_finite";
    case QueryStatus::kFclFailure: return "fcl_failure";
  }
  return "unknown";
}

BoundaryDistanceField::BoundaryDistanceField(TriangleMesh mesh) : mesh_(std::move(mesh)), impl_(new Impl) {
  stats_ = ComputeMeshStatistics(mesh_);
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
  std::map<std::pair<int, int>, Eigen::Vector3d> edge_sum;
  for (std::size_t t = 0; t < T.size(); ++t) {
    const Eigen::Vector3d &a = V[T[t][0]], &b = V[T[t][1]], &c = V[T[t][2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    m.face_normal[t] = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    // Angle-weighted vertex pseudonormals (a degenerate face has zero normal and adds nothing).
    m.vertex_normal[T[t][0]] += AngleAt(a, b, c) * m.face_normal[t];
    m.vertex_normal[T[t][1]] += AngleAt(b, c, a) * m.face_normal[t];
    m.vertex_normal[T[t][2]] += AngleAt(c, a, b) * m.face_normal[t];
    for (int e = 0; e < 3; ++e) {
      const int i = T[t][e], j = T[t][(e + 1) % 3];
      // Edge pseudonormal: the sum of the two faces' normals (an Eigen vector is not zero-initialised: insert Zero).
      edge_sum.try_emplace({std::min(i, j), std::max(i, j)}, Eigen::Vector3d::Zero()).first->second += m.face_normal[t];
    }
  }
  for (Eigen::Vector3d& n : m.vertex_normal) n.normalize();
  for (std::size_t t = 0; t < T.size(); ++t) {
    for (int e = 0; e < 3; ++e) {
      const int i = T[t][e], j = T[t][(e + 1) % 3];
      m.edge_normal[t][e] = edge_sum.at({std::min(i, j), std::max(i, j)}).normalized();
    }
  }
  m.bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(T.size());
  for (const Eigen::Vector3i& t : T) triangles.emplace_back(t[0], t[1], t[2]);
  m.bvh->beginModel(static_cast<int>(T.size()), static_cast<int>(V.size()));
  m.bvh->addSubModel(V, triangles);
  m.bvh->endModel();
  m.bvh->computeLocalAABB();
}

BoundaryDistanceField::~BoundaryDistanceField() = default;

struct SignedDistanceQuery::State {
  // FCL's own traversal node for OBBRSS mesh vs shape, driven directly: fcl::distance() would rebuild the point's
  // bounding volume through Sphere::getBoundVertices(), which allocates a std::vector on every call.
  using Solver = fcl::detail::GJKSolver_libccd<double>;  // DEPENDENCIES.md: GST_INDEP is broken in FCL 0.7
  using Node = fcl::detail::MeshShapeDistanceTraversalNodeOBBRSS<fcl::Sphered, Solver>;
  fcl::Sphered point{0.0};  // a zero-radius sphere: FCL's point query
  Solver solver;
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  Node node;
  State() {
    request.enable_nearest_points = false;  // only the closest triangle is needed; its point is recomputed exactly
    request.enable_signed_distance = false;
    request.rel_err = 0;
    request.abs_err = 0;
    node.request = request;
    node.result = &result;
    node.model2 = &point;
    node.nsolver = &solver;
    node.tf1 = fcl::Transform3d::Identity();
    node.tf2 = fcl::Transform3d::Identity();
    // The point's bounding volume: a degenerate OBB and RSS at the point, axes along the frame.
    node.model2_bv.obb.axis.setIdentity();
    node.model2_bv.obb.extent.setZero();
    node.model2_bv.rss.axis.setIdentity();
    node.model2_bv.rss.l[0] = node.model2_bv.rss.l[1] = 0;
    node.model2_bv.rss.r = 0;
  }
};

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
  const BoundaryDistanceField::Impl& m = field->impl();
  fcl::BVHModel<fcl::OBBRSSd>& bvh = *m.bvh;
  s.result.clear();
  s.node.model1 = &bvh;
  s.node.vertices = bvh.vertices;
  s.node.tri_indices = bvh.tri_indices;
  s.node.tf2.translation() = q;
  s.node.model2_bv.obb.To = q;
  s.node.model2_bv.rss.To = q;
  fcl::detail::distance(&s.node, nullptr, 2);
  const intptr_t t = s.result.b1;
  if (t < 0 || static_cast<std::size_t>(t) >= field->mesh().triangles.size()) {
    return out->status = QueryStatus::kFclFailure;
  }
  const Eigen::Vector3i& tri = field->mesh().triangles[static_cast<std::size_t>(t)];
  const auto& V = field->mesh().vertices;
  Feature feature = Feature::kFace;
  const Eigen::Vector3d c = ClosestPointOnTriangle(q, V[tri[0]], V[tri[1]], V[tri[2]], &feature);
  Eigen::Vector3d pseudonormal;
  switch (feature) {
    case Feature::kFace: pseudonormal = m.face_normal[t]; break;
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
  return out->status = QueryStatus::kOk;
}

}  // namespace robossis::geometry
