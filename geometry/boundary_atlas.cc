// The boundary atlas: build, save (atomically), load (verified), look up.

#include "geometry/boundary_atlas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "src/core/files.h"
#include "src/core/json_integer.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::geometry {

namespace {

constexpr const char* kFormat = "robossis-boundary-atlas";
// 2: standard FNV-1a offset basis, geometry fingerprint; 3: every grid node listed, empty ones too ("empty")
constexpr int kVersion = 3;

std::uint64_t Fnv1a64(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;  // the FNV-1a 64-bit offset basis
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

std::string Hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

int NodeCount(const std::array<GridAxis, 3>& g) { return g[0].count * g[1].count * g[2].count; }
int Flat(const std::array<GridAxis, 3>& g, const Eigen::Vector3i& n) {
  return n.x() + g[0].count * (n.y() + g[1].count * n.z());
}
Eigen::Vector3d NodeValue(const std::array<GridAxis, 3>& g, const Eigen::Vector3i& n) {
  return {g[0].min + g[0].step * n.x(), g[1].min + g[1].step * n.y(), g[2].min + g[2].step * n.z()};
}

GridAxis Axis(double min, double max, double step) {
  GridAxis a;
  a.min = min;
  a.step = step;
  a.count = static_cast<int>(std::lround((max - min) / step)) + 1;
  return a;
}

nlohmann::ordered_json GridJson(const std::array<GridAxis, 3>& g, double scale) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const GridAxis& a : g) j.push_back({{"min", a.min * scale}, {"step", a.step * scale}, {"count", a.count}});
  return j;
}

std::array<GridAxis, 3> GridFromJson(const nlohmann::json& j, double scale, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error(where + ": expected an array of 3 axes");
  std::array<GridAxis, 3> g;
  for (int a = 0; a < 3; ++a) {
    g[a].min = j[a].at("min").get<double>() / scale;
    g[a].step = j[a].at("step").get<double>() / scale;
    g[a].count = JsonInteger<int>(j[a].at("count"), where + "[" + std::to_string(a) + "].count");
  }
  return g;
}

void ValidateGrid(const std::array<GridAxis, 3>& g, const std::string& name) {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(g[a].min) || !std::isfinite(g[a].step) || g[a].count < 1 || g[a].count > 1000 ||
        (g[a].count > 1 && !(g[a].step > 0))) {
      throw std::invalid_argument(name + " axis " + std::to_string(a) +
                                  ": expected a finite min, a step > 0 and 1..1000 nodes");
    }
  }
}

}  // namespace

std::string Fnv1a64Hex(const std::string& bytes) { return Hex(Fnv1a64(bytes)); }

std::string GeometryFingerprint(const robot::RsrModel& rsr, const robot::Sigma7Model& hc) {
  std::string text;
  char buf[40];
  auto add = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.17g,", v);
    text += buf;
  };
  const robot::RsrGeometry& g = rsr.geometry();
  for (int i = 0; i < robot::kNumArms; ++i) {
    add(g.arm_angles_rad[i]);
    for (int k = 0; k < 3; ++k) add(g.p_FA[i][k]), add(g.p_MB[i][k]);
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) add(g.X_FM_home.matrix()(r, c));
  }
  add(g.limits.stroke_min_m), add(g.limits.stroke_max_m), add(g.limits.spherical_cone_max_rad),
      add(g.limits.rotary_max_rad);
  const robot::Sigma7Geometry& h = hc.geometry();
  for (double v : {h.a_m, h.b_m, h.r_m, h.c_m, h.f_m, h.s_m, h.tilt_rad, h.theta1_min_rad, h.theta1_max_rad,
                   h.theta3_min_rad, h.theta3_max_rad, h.max_force_n, h.max_torque_nm}) {
    add(v);
  }
  for (double v : h.chain_angles_rad) add(v);
  for (int k = 0; k < 3; ++k) add(h.wrist_half_range_rad[k]);
  return Hex(Fnv1a64(text));
}

void BoundaryAtlas::RequireBuiltFor(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                    const std::string& where) const {
  const std::string expected = GeometryFingerprint(rsr, hc);
  if (fingerprint_ != expected) {
    throw std::runtime_error(where + ": the atlas was built for another robot geometry or other limits (fingerprint " +
                             fingerprint_ + ", this configuration's " + expected +
                             "); rebuild it with `robossis workspace atlas` under this --data-dir");
  }
}

namespace {
bool Covers(const std::array<GridAxis, 3>& g, const Eigen::Vector3d& x, double max_half_step) {
  for (int k = 0; k < 3; ++k) {
    // A one-node axis has no step to speak of (its declared step is a placeholder): only the cap applies.
    const double half = g[k].count > 1 ? std::min(0.5 * g[k].step, max_half_step) : max_half_step;
    if (!(x[k] >= g[k].min - half && x[k] <= g[k].max() + half)) return false;
  }
  return true;
}
}  // namespace

bool BoundaryAtlas::CoversOrientation(const Eigen::Vector3d& rpy_rad) const noexcept {
  return Covers(spec_.orientation_grid, rpy_rad, kMaxCoverageHalfStepRad);
}
bool BoundaryAtlas::CoversPosition(const Eigen::Vector3d& p_FM_m) const noexcept {
  return Covers(spec_.position_grid, p_FM_m, kMaxCoverageHalfStepM);
}

void MarkOffGrid(const BoundaryAtlas* atlas, const Eigen::Isometry3d& X_FM, PoseBoundaryResult* r) noexcept {
  if (atlas == nullptr) return;
  if (r->live_dexterous_slice == nullptr && !atlas->CoversOrientation(RpyFromRotation(X_FM.linear()))) {
    r->translation.status = QueryStatus::kOffGrid;
  }
  if (r->live_rotational_slice == nullptr && !atlas->CoversPosition(X_FM.translation())) {
    r->rotation.status = QueryStatus::kOffGrid;
  }
}

int GridAxis::Nearest(double x) const noexcept {
  if (count <= 1 || !(step > 0) || !std::isfinite(x)) return 0;
  const double i = std::round((x - min) / step);
  if (i <= 0) return 0;
  if (i >= count - 1) return count - 1;
  return static_cast<int>(i);
}

AtlasSpec AtlasSpec::Default(const robot::RsrModel& rsr) {
  AtlasSpec s;
  s.orientation_grid = {Axis(DegToRad(-20), DegToRad(20), DegToRad(5)), Axis(DegToRad(-20), DegToRad(20), DegToRad(5)),
                        Axis(DegToRad(-40), DegToRad(40), DegToRad(10))};
  const Eigen::Vector3d home = rsr.geometry().X_FM_home.translation();
  s.position_grid = {Axis(home.x() - 0.12, home.x() + 0.12, 0.03), Axis(home.y() - 0.12, home.y() + 0.12, 0.03),
                     Axis(home.z() - 0.06, home.z() + 0.06, 0.02)};
  // Mesh resolution: the nearest-node error of this grid (millimetres, degrees; README "Atlas error") dwarfs the
  // mesh's own chord error at these spacings, and coarser meshes keep the atlas small and quick to load.
  s.dexterous_resolution_m = 0.006;
  s.rotational_resolution_rad = DegToRad(3);
  return s;
}

AtlasSpec AtlasSpec::Coarse(const robot::RsrModel& rsr) {
  AtlasSpec s;
  s.orientation_grid = {Axis(DegToRad(-10), DegToRad(10), DegToRad(10)), Axis(0, 0, 1),
                        Axis(DegToRad(-20), DegToRad(20), DegToRad(20))};
  const Eigen::Vector3d home = rsr.geometry().X_FM_home.translation();
  s.position_grid = {Axis(home.x() - 0.05, home.x() + 0.05, 0.05), Axis(home.y(), home.y(), 1),
                     Axis(home.z(), home.z(), 1)};
  s.dexterous_resolution_m = 0.01;
  s.rotational_resolution_rad = DegToRad(4);
  return s;
}

void AtlasSpec::Validate() const {
  ValidateGrid(orientation_grid, "atlas orientation grid");
  ValidateGrid(position_grid, "atlas position grid");
  if (!(dexterous_resolution_m > 0) || !std::isfinite(dexterous_resolution_m)) {
    throw std::invalid_argument("atlas dexterous resolution must be > 0 mm");
  }
  if (!(rotational_resolution_rad > 0) || !std::isfinite(rotational_resolution_rad)) {
    throw std::invalid_argument("atlas rotational resolution must be > 0 deg");
  }
}

BoundaryAtlas::BoundaryAtlas(AtlasSpec spec, std::vector<AtlasSlice> dexterous, std::vector<AtlasSlice> rotational)
    : spec_(std::move(spec)), dexterous_(std::move(dexterous)), rotational_(std::move(rotational)) {
  spec_.Validate();
  dexterous_index_.assign(static_cast<std::size_t>(NodeCount(spec_.orientation_grid)), -1);
  rotational_index_.assign(static_cast<std::size_t>(NodeCount(spec_.position_grid)), -1);
  auto index = [](const std::vector<AtlasSlice>& slices, const std::array<GridAxis, 3>& g, std::vector<int>& table,
                  const char* name) {
    for (std::size_t s = 0; s < slices.size(); ++s) {
      const Eigen::Vector3i& n = slices[s].node;
      for (int a = 0; a < 3; ++a) {
        if (n[a] < 0 || n[a] >= g[a].count) throw std::invalid_argument(std::string(name) + " slice node out of grid");
      }
      if (!slices[s].field) throw std::invalid_argument(std::string(name) + " slice without a mesh");
      table[static_cast<std::size_t>(Flat(g, n))] = static_cast<int>(s);
    }
  };
  index(dexterous_, spec_.orientation_grid, dexterous_index_, "dexterous");
  index(rotational_, spec_.position_grid, rotational_index_, "rotational");
}

const AtlasSlice* BoundaryAtlas::FindDexterous(const Eigen::Vector3d& rpy_rad) const noexcept {
  if (dexterous_index_.empty()) return nullptr;
  const auto& g = spec_.orientation_grid;
  const Eigen::Vector3i n(g[0].Nearest(rpy_rad.x()), g[1].Nearest(rpy_rad.y()), g[2].Nearest(rpy_rad.z()));
  const int s = dexterous_index_[static_cast<std::size_t>(Flat(g, n))];
  return s < 0 ? nullptr : &dexterous_[static_cast<std::size_t>(s)];
}

const AtlasSlice* BoundaryAtlas::FindRotational(const Eigen::Vector3d& p_FM_m) const noexcept {
  if (rotational_index_.empty()) return nullptr;
  const auto& g = spec_.position_grid;
  const Eigen::Vector3i n(g[0].Nearest(p_FM_m.x()), g[1].Nearest(p_FM_m.y()), g[2].Nearest(p_FM_m.z()));
  const int s = rotational_index_[static_cast<std::size_t>(Flat(g, n))];
  return s < 0 ? nullptr : &rotational_[static_cast<std::size_t>(s)];
}

BoundaryAtlas BuildAtlas(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const AtlasSpec& spec,
                         const std::filesystem::path& dir, const AtlasProgress& progress) {
  spec.Validate();
  StagedOutputDir out(dir);
  BoundaryAtlas atlas = BuildAtlasIn(rsr, hc, spec, out.staging(), progress);
  out.Commit();
  return atlas;
}

BoundaryAtlas BuildAtlasIn(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const AtlasSpec& spec,
                           const std::filesystem::path& dir, const AtlasProgress& progress) {
  spec.Validate();
  nlohmann::ordered_json manifest;
  manifest["format"] = kFormat;
  manifest["version"] = kVersion;
  manifest["units"] = {{"dexterous_mesh", "mm, position of the moving-ring centre P in the fixed-ring frame F"},
                       {"rotational_mesh", "deg, (roll, pitch, yaw) of R_FM with R = Rz(yaw) Ry(pitch) Rx(roll)"},
                       {"orientation_grid", "deg"},
                       {"position_grid", "mm"}};
  manifest["orientation_grid"] = GridJson(spec.orientation_grid, kRadToDeg);
  manifest["position_grid"] = GridJson(spec.position_grid, kMToMm);
  manifest["dexterous_resolution_mm"] = spec.dexterous_resolution_m * kMToMm;
  manifest["rotational_resolution_deg"] = spec.rotational_resolution_rad * kRadToDeg;
  const std::string fingerprint = GeometryFingerprint(rsr, hc);
  manifest["geometry_fingerprint"] = fingerprint;
  const int total = NodeCount(spec.orientation_grid) + NodeCount(spec.position_grid);
  int done = 0;
  std::vector<AtlasSlice> slices[2];
  nlohmann::ordered_json entries[2] = {nlohmann::ordered_json::array(), nlohmann::ordered_json::array()};
  for (int family = 0; family < 2; ++family) {
    const bool dexterous = family == 0;
    const auto& g = dexterous ? spec.orientation_grid : spec.position_grid;
    const SliceKind kind = dexterous ? SliceKind::kRsrDexterous : SliceKind::kRsrRotational;
    const double scale = EdgeUnitScale(kind);
    for (int k = 0; k < g[2].count; ++k) {
      for (int j = 0; j < g[1].count; ++j) {
        for (int i = 0; i < g[0].count; ++i) {
          const Eigen::Vector3i node(i, j, k);
          SliceSpec s;
          s.kind = kind;
          s.fixed = NodeValue(g, node);
          s.resolution = dexterous ? spec.dexterous_resolution_m : spec.rotational_resolution_rad;
          WorkspaceSlice slice;
          bool empty = false;
          try {
            slice = GenerateSlice(rsr, hc, s);
          } catch (const std::runtime_error&) {
            empty = true;  // the node's pose is unreachable: no slice (documented in the manifest)
          }
          if (progress) progress(++done, total);
          const Eigen::Vector3d fixed = s.fixed * (dexterous ? kRadToDeg : kMToMm);
          const char* fixed_key = dexterous ? "rpy_deg" : "position_mm";
          if (empty || slice.mesh.triangles.empty()) {
            // Listed all the same, so the manifest names every node and a truncated one is detectable.
            entries[family].push_back({{"node", {i, j, k}}, {fixed_key, {fixed.x(), fixed.y(), fixed.z()}},
                                       {"empty", true}});
            continue;
          }
          const std::string file = std::string(dexterous ? "dexterous/d_" : "rotational/r_") + std::to_string(i) +
                                   "_" + std::to_string(j) + "_" + std::to_string(k) + ".ply";
          const std::string bytes = BinaryPlyBytes(slice.mesh, scale);
          WriteFileAtomically(dir / file, bytes);
          entries[family].push_back({{"node", {i, j, k}},
                                     {fixed_key, {fixed.x(), fixed.y(), fixed.z()}},
                                     {"empty", false},
                                     {"file", file},
                                     {"bytes", bytes.size()},
                                     {"fnv1a64", Hex(Fnv1a64(bytes))},
                                     {"volume", slice.stats.volume * scale * scale * scale},
                                     {"triangles", slice.stats.triangles}});
          // Re-read the bytes as Load() will, so the in-memory atlas equals the saved one (float32 coordinates).
          AtlasSlice a;
          a.kind = kind;
          a.node = node;
          a.fixed = s.fixed;
          a.field = std::make_shared<BoundaryDistanceField>(ParseBinaryPly(bytes, scale, file));
          slices[family].push_back(std::move(a));
        }
      }
    }
  }
  manifest["dexterous_slices"] = entries[0];
  manifest["rotational_slices"] = entries[1];
  WriteFileAtomically(dir / "manifest.json", manifest.dump(1) + "\n");
  BoundaryAtlas atlas(spec, std::move(slices[0]), std::move(slices[1]));
  atlas.set_fingerprint(fingerprint);
  return atlas;
}

BoundaryAtlas BoundaryAtlas::Load(const std::filesystem::path& dir) {
  const std::filesystem::path manifest_file = dir / "manifest.json";
  if (!std::filesystem::is_directory(dir)) throw std::runtime_error(dir.string() + ": atlas folder does not exist");
  if (!std::filesystem::exists(manifest_file)) {
    throw std::runtime_error(manifest_file.string() + ": missing (not an atlas, or an incomplete one)");
  }
  const std::string where = manifest_file.string();
  try {
    const nlohmann::json m = nlohmann::json::parse(ReadTextFile(manifest_file));
    if (m.at("format").get<std::string>() != kFormat) {
      throw std::runtime_error("format: expected \"" + std::string(kFormat) + "\" (not an atlas)");
    }
    const int version = JsonInteger<int>(m.at("version"), "version");
    if (version != kVersion) {
      throw std::runtime_error("version " + std::to_string(version) + ": expected " + std::to_string(kVersion) +
                               " (an atlas of another version: rebuild the atlas with `robossis workspace atlas`)");
    }
    AtlasSpec spec;
    spec.orientation_grid = GridFromJson(m.at("orientation_grid"), kRadToDeg, "orientation_grid");
    spec.position_grid = GridFromJson(m.at("position_grid"), kMToMm, "position_grid");
    spec.dexterous_resolution_m = m.at("dexterous_resolution_mm").get<double>() * kMmToM;
    spec.rotational_resolution_rad = m.at("rotational_resolution_deg").get<double>() * kDegToRad;
    spec.Validate();
    std::vector<AtlasSlice> slices[2];
    for (int family = 0; family < 2; ++family) {
      const bool dexterous = family == 0;
      const SliceKind kind = dexterous ? SliceKind::kRsrDexterous : SliceKind::kRsrRotational;
      const auto& g = dexterous ? spec.orientation_grid : spec.position_grid;
      const char* list = dexterous ? "dexterous_slices" : "rotational_slices";
      const nlohmann::json& entries = m.at(list);
      if (!entries.is_array()) throw std::runtime_error(std::string(list) + ": expected an array");
      // Every node of the grid exactly once (empty ones too): a manifest that lists fewer is partial. Counted before
      // anything is allocated for the grid.
      const std::size_t nodes = static_cast<std::size_t>(NodeCount(g));
      if (entries.size() != nodes) {
        throw std::runtime_error(std::string(list) + ": lists " + std::to_string(entries.size()) + " of the grid's " +
                                 std::to_string(nodes) +
                                 " nodes; expected every node (a partial manifest: rebuild the atlas with "
                                 "`robossis workspace atlas`)");
      }
      std::vector<char> listed(nodes, 0);
      std::size_t listed_count = 0;
      for (const nlohmann::json& e : entries) {
        const auto node = e.at("node");
        const std::string node_name = std::string(list) + "[" + std::to_string(listed_count) + "].node";
        const Eigen::Vector3i n(JsonInteger<int>(node.at(0), node_name), JsonInteger<int>(node.at(1), node_name),
                                JsonInteger<int>(node.at(2), node_name));
        for (int k = 0; k < 3; ++k) {
          if (n[k] < 0 || n[k] >= g[k].count) throw std::runtime_error(node_name + ": node outside the grid");
        }
        char& seen = listed[static_cast<std::size_t>(Flat(g, n))];
        if (seen) {
          throw std::runtime_error(node_name + ": node (" + std::to_string(n.x()) + ", " + std::to_string(n.y()) +
                                   ", " + std::to_string(n.z()) + ") listed twice");
        }
        seen = 1;
        ++listed_count;
        if (e.at("empty").get<bool>()) continue;
        const std::string file = e.at("file").get<std::string>();
        if (file.find("..") != std::string::npos || file.empty() || file.front() == '/') {
          throw std::runtime_error("slice file '" + file + "' is not a relative path inside the atlas");
        }
        const std::string bytes = ReadTextFile(dir / file);
        const std::size_t expected_bytes = JsonInteger<std::size_t>(e.at("bytes"), "slice '" + file + "': bytes");
        if (bytes.size() != expected_bytes || Hex(Fnv1a64(bytes)) != e.at("fnv1a64").get<std::string>()) {
          throw std::runtime_error("slice file '" + file + "' does not match its size/hash (corrupt or partial atlas)");
        }
        AtlasSlice a;
        a.kind = kind;
        a.node = n;
        a.fixed = NodeValue(g, a.node);
        a.field =
            std::make_shared<BoundaryDistanceField>(ParseBinaryPly(bytes, EdgeUnitScale(kind), (dir / file).string()));
        slices[family].push_back(std::move(a));
      }
    }
    BoundaryAtlas atlas(spec, std::move(slices[0]), std::move(slices[1]));
    atlas.set_fingerprint(m.at("geometry_fingerprint").get<std::string>());
    return atlas;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(where + ": malformed manifest (" + e.what() + ")");
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(where + ": " + e.what());
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    if (what.rfind(dir.string(), 0) == 0) throw;
    throw std::runtime_error(where + ": " + what);
  }
}

void AtlasPoseQuery::Query(const BoundaryAtlas& atlas, const Eigen::Isometry3d& X_FM, double position_radius_m,
                           double angle_radius_rad, PoseBoundaryResult* out) noexcept {
  const Eigen::Vector3d p = X_FM.translation();
  const Eigen::Vector3d rpy = RpyFromRotation(X_FM.linear());
  out->dexterous_slice = atlas.FindDexterous(rpy);
  out->rotational_slice = atlas.FindRotational(p);
  out->live_dexterous_slice = out->live_rotational_slice = nullptr;
  QueryFields(out->dexterous_slice ? out->dexterous_slice->field.get() : nullptr,
              out->rotational_slice ? out->rotational_slice->field.get() : nullptr, p, rpy, position_radius_m,
              angle_radius_rad, out);
}

void AtlasPoseQuery::QueryFields(const BoundaryDistanceField* translation_field,
                                 const BoundaryDistanceField* rotation_field, const Eigen::Vector3d& p_FM,
                                 const Eigen::Vector3d& rpy, double position_radius_m, double angle_radius_rad,
                                 PoseBoundaryResult* out) noexcept {
  translation_query_.Query(translation_field, p_FM, position_radius_m, &out->translation);
  rotation_query_.Query(rotation_field, rpy, angle_radius_rad, &out->rotation);
}

}  // namespace robossis::geometry
