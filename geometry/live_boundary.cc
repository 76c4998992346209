#include "geometry/live_boundary.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "src/core/pose.h"

namespace robossis::geometry {

namespace {

constexpr int kDexterous = 0;
constexpr int kRotational = 1;

int FamilyOf(SliceKind kind) {
  if (kind == SliceKind::kRsrDexterous) return kDexterous;
  if (kind == SliceKind::kRsrRotational) return kRotational;
  throw std::invalid_argument("live boundary: only RSR dexterous and rotational slices are pose dependent");
}

}  // namespace

void LiveBoundaryOptions::Validate() const {
  auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0)) {
      throw std::invalid_argument(std::string("live boundary: ") + name + " must be a positive number");
    }
  };
  positive(dexterous_resolution_m, "dexterous_resolution_m");
  positive(rotational_resolution_rad, "rotational_resolution_rad");
  positive(orientation_tolerance_rad, "orientation_tolerance_rad");
  positive(position_tolerance_m, "position_tolerance_m");
}

LiveBoundary::LiveBoundary(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, LiveBoundaryOptions options)
    : rsr_(rsr), hc_(hc), options_(options) {
  options_.Validate();
}

LiveBoundary::~LiveBoundary() { Stop(); }

void LiveBoundary::PostPose(const Eigen::Isometry3d& X_FM) noexcept {
  PostPose(X_FM.translation(), RpyFromRotation(X_FM.linear()));
}

void LiveBoundary::PostPose(const Eigen::Vector3d& p, const Eigen::Vector3d& rpy) noexcept {
  // Sequence lock, writer side (single writer): odd while writing.
  const std::uint64_t s = pose_sequence_.load(std::memory_order_relaxed);
  pose_sequence_.store(s + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  for (int i = 0; i < 3; ++i) {
    pose_[i].store(p[i], std::memory_order_relaxed);
    pose_[3 + i].store(rpy[i], std::memory_order_relaxed);
  }
  pose_sequence_.store(s + 2, std::memory_order_release);
}

bool LiveBoundary::LatestPose(Eigen::Vector3d* p_FM, Eigen::Vector3d* rpy) const noexcept {
  for (;;) {
    const std::uint64_t before = pose_sequence_.load(std::memory_order_acquire);
    if (before == 0) return false;
    if (before % 2 == 1) continue;  // being written
    for (int i = 0; i < 3; ++i) {
      (*p_FM)[i] = pose_[i].load(std::memory_order_relaxed);
      (*rpy)[i] = pose_[3 + i].load(std::memory_order_relaxed);
    }
    std::atomic_thread_fence(std::memory_order_acquire);
    if (pose_sequence_.load(std::memory_order_relaxed) == before) return true;
  }
}

const LiveSlice* LiveBoundary::Acquire(int family) noexcept {
  // Hazard pointer: announce the slice, then check it is still the published one (else it may already be retired).
  const LiveSlice* slice = published_[family].load();
  for (;;) {
    hazard_[family].store(slice);
    const LiveSlice* again = published_[family].load();
    if (again == slice) return slice;
    slice = again;
  }
}

bool LiveBoundary::NeedsRefresh(SliceKind kind, const Eigen::Vector3d& p_FM, const Eigen::Vector3d& rpy) const noexcept {
  const bool dexterous = kind == SliceKind::kRsrDexterous;
  const int family = dexterous ? kDexterous : kRotational;
  std::lock_guard<std::mutex> lock(refresh_mutex_);
  if (!generated_[family]) return true;
  return dexterous ? (rpy - generated_at_[family]).norm() > options_.orientation_tolerance_rad
                   : (p_FM - generated_at_[family]).norm() > options_.position_tolerance_m;
}

void LiveBoundary::MarkGenerated(SliceKind kind, const Eigen::Vector3d& fixed) {
  const int family = FamilyOf(kind);
  std::lock_guard<std::mutex> lock(refresh_mutex_);
  generated_at_[family] = fixed;
  generated_[family] = true;
}

std::unique_ptr<LiveSlice> LiveBoundary::Generate(SliceKind kind, const Eigen::Vector3d& fixed) {
  MarkGenerated(kind, fixed);
  const double resolution =
      kind == SliceKind::kRsrDexterous ? options_.dexterous_resolution_m : options_.rotational_resolution_rad;
  WorkspaceSlice slice;
  try {
    slice = GenerateSlice(rsr_, hc_, {kind, fixed, resolution});
  } catch (const std::runtime_error&) {
    return nullptr;  // empty slice: the pose is unreachable; the caller keeps the previous slice or the atlas
  }
  auto live = std::make_unique<LiveSlice>();
  live->kind = kind;
  live->fixed = fixed;
  live->field = std::make_unique<const BoundaryDistanceField>(std::move(slice.mesh), slice.stats);
  return live;
}

void LiveBoundary::Publish(std::unique_ptr<LiveSlice> slice) {
  if (!slice) return;
  const int family = FamilyOf(slice->kind);
  std::lock_guard<std::mutex> lock(refresh_mutex_);
  const LiveSlice* raw = slice.get();
  owned_.push_back(std::move(slice));
  published_[family].store(raw);
  ++published_count_;
  // Free every slice that is neither published nor announced by the real-time thread (see Acquire).
  const std::array<const LiveSlice*, 4> keep = {published_[0].load(), published_[1].load(), hazard_[0].load(),
                                                hazard_[1].load()};
  std::erase_if(owned_, [&keep](const std::unique_ptr<LiveSlice>& s) {
    return std::find(keep.begin(), keep.end(), s.get()) == keep.end();
  });
}

int LiveBoundary::RefreshNow() {
  Eigen::Vector3d p, rpy;
  if (!LatestPose(&p, &rpy)) return 0;
  int published = 0;
  if (NeedsRefresh(SliceKind::kRsrDexterous, p, rpy)) {
    if (auto s = Generate(SliceKind::kRsrDexterous, rpy)) {
      Publish(std::move(s));
      ++published;
    }
  }
  if (NeedsRefresh(SliceKind::kRsrRotational, p, rpy)) {
    if (auto s = Generate(SliceKind::kRsrRotational, p)) {
      Publish(std::move(s));
      ++published;
    }
  }
  return published;
}

void LiveBoundary::Start(double idle_poll_s) {
  if (thread_.joinable()) return;
  stop_ = false;
  const auto idle = std::chrono::duration<double>(std::max(1e-4, idle_poll_s));
  thread_ = std::thread([this, idle] {
    while (!stop_.load()) {
      if (RefreshNow() == 0) std::this_thread::sleep_for(idle);
    }
  });
}

void LiveBoundary::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void LivePoseQuery::Query(LiveBoundary& live, const BoundaryAtlas* atlas, const Eigen::Isometry3d& X_FM,
                          double position_radius_m, double angle_radius_rad, PoseBoundaryResult* out) noexcept {
  const Eigen::Vector3d p = X_FM.translation();
  const Eigen::Vector3d rpy = RpyFromRotation(X_FM.linear());
  live.PostPose(p, rpy);
  const LiveSlice* live_dexterous = live.AcquireDexterous();
  const LiveSlice* live_rotational = live.AcquireRotational();
  out->dexterous_slice = atlas ? atlas->FindDexterous(rpy) : nullptr;
  out->rotational_slice = atlas ? atlas->FindRotational(p) : nullptr;
  // For each family, the slice made at the pose nearer to the current one.
  const bool use_live_dexterous =
      live_dexterous && (!out->dexterous_slice ||
                         (rpy - live_dexterous->fixed).norm() <= (rpy - out->dexterous_slice->fixed).norm());
  const bool use_live_rotational =
      live_rotational && (!out->rotational_slice ||
                          (p - live_rotational->fixed).norm() <= (p - out->rotational_slice->fixed).norm());
  out->live_dexterous_slice = use_live_dexterous ? live_dexterous : nullptr;
  out->live_rotational_slice = use_live_rotational ? live_rotational : nullptr;
  const BoundaryDistanceField* translation_field =
      use_live_dexterous ? live_dexterous->field.get()
                         : (out->dexterous_slice ? out->dexterous_slice->field.get() : nullptr);
  const BoundaryDistanceField* rotation_field =
      use_live_rotational ? live_rotational->field.get()
                          : (out->rotational_slice ? out->rotational_slice->field.get() : nullptr);
  fields_.QueryFields(translation_field, rotation_field, p, rpy, position_radius_m, angle_radius_rad, out);
}

RefreshTiming MeasureRefreshTiming(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                   const LiveBoundaryOptions& options, const Eigen::Isometry3d& X_FM,
                                   int repetitions) {
  LiveBoundary live(rsr, hc, options);
  const Eigen::Vector3d p = X_FM.translation();
  const Eigen::Vector3d rpy = RpyFromRotation(X_FM.linear());
  auto median_seconds = [&](SliceKind kind, const Eigen::Vector3d& fixed) {
    std::vector<double> seconds;
    for (int k = 0; k < std::max(1, repetitions); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      if (!live.Generate(kind, fixed)) {
        throw std::invalid_argument("refresh timing: the slice at this pose is empty (pose unreachable)");
      }
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(seconds.begin(), seconds.begin() + seconds.size() / 2, seconds.end());
    return seconds[seconds.size() / 2];
  };
  return {median_seconds(SliceKind::kRsrDexterous, rpy), median_seconds(SliceKind::kRsrRotational, p)};
}

LiveStaleness WorstCaseStaleness(const RefreshTiming& timing, const LiveBoundaryOptions& options,
                                 double linear_speed_mps, double angular_speed_radps) {
  const double age_s = 2 * timing.cycle_s();
  return {options.orientation_tolerance_rad + angular_speed_radps * age_s,
          options.position_tolerance_m + linear_speed_mps * age_s};
}

SimulatedRefresher::SimulatedRefresher(LiveBoundary& live, double latency_s) : live_(live), latency_s_(latency_s) {
  if (!(std::isfinite(latency_s) && latency_s >= 0)) {
    throw std::invalid_argument("simulated refresh: latency_s must be a non-negative number");
  }
}

void SimulatedRefresher::Reset() {
  pending_.clear();
  busy_ = false;
}

void SimulatedRefresher::Step(double now_s) {
  if (busy_ && now_s + 1e-12 >= ready_at_s_) {
    // Generated now, from the poses the refresh started at: the same slices as generating them at its start, without
    // holding them through the latency beside the published ones (about 11 MB per dexterous slice at home).
    for (const PendingSlice& p : pending_) live_.Publish(live_.Generate(p.kind, p.fixed));
    pending_.clear();
    busy_ = false;
  }
  if (busy_) return;
  Eigen::Vector3d p, rpy;
  if (!live_.LatestPose(&p, &rpy)) return;
  if (live_.NeedsRefresh(SliceKind::kRsrDexterous, p, rpy)) {
    live_.MarkGenerated(SliceKind::kRsrDexterous, rpy);
    pending_.push_back({SliceKind::kRsrDexterous, rpy});
  }
  if (live_.NeedsRefresh(SliceKind::kRsrRotational, p, rpy)) {
    live_.MarkGenerated(SliceKind::kRsrRotational, p);
    pending_.push_back({SliceKind::kRsrRotational, p});
  }
  if (pending_.empty()) return;
  busy_ = true;
  ready_at_s_ = now_s + latency_s_;
}

}  // namespace robossis::geometry
