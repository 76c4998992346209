#include "robot/sim/scenario.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "robot/rsr_kinematics.h"
#include "src/core/units.h"

namespace robossis::sim {

const char* ToString(ScenarioKind kind) {
  switch (kind) {
    case ScenarioKind::kSinusoid: return "sinusoid";
    case ScenarioKind::kReduction: return "reduction";
  }
  return "unknown";
}

ScenarioKind ParseScenarioKind(const std::string& text) {
  if (text == "sinusoid") return ScenarioKind::kSinusoid;
  if (text == "reduction") return ScenarioKind::kReduction;
  throw std::invalid_argument("--scenario: expected 'sinusoid' or 'reduction', got '" + text + "'");
}

void ValidateScenarioParams(const ScenarioParams& p, const SimConfig& config) {
  auto fmt = [](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  // The drives can hold about 3 x 1100 N along the axis; beyond 5000 N or 500 N·m the model is meaningless.
  if (!std::isfinite(p.load_n) || p.load_n < 0 || p.load_n > 5000) {
    throw std::invalid_argument("--load-n: expected a traction force in [0, 5000] N, got " + fmt(p.load_n));
  }
  if (!std::isfinite(p.load_nm) || p.load_nm < 0 || p.load_nm > 500) {
    throw std::invalid_argument("--load-nm: expected a traction torque in [0, 500] N·m, got " + fmt(p.load_nm));
  }
  if (!std::isfinite(p.duration_s) || p.duration_s <= 0 || p.duration_s > 3600) {
    throw std::invalid_argument("--duration-s: expected a simulated duration in (0, 3600] s, got " + fmt(p.duration_s));
  }
  if (p.duration_s < 10 * config.physics.step_s()) {
    throw std::invalid_argument("--duration-s: expected at least 10 physics steps (" + fmt(10 * config.physics.step_s()) +
                                " s), got " + fmt(p.duration_s));
  }
  if (!std::isfinite(p.record_hz) || p.record_hz <= 0 || p.record_hz > config.physics.step_hz) {
    throw std::invalid_argument("record rate: expected (0, step_hz] Hz, got " + fmt(p.record_hz));
  }
}

namespace {
double Smoothstep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}
double MinimumJerk(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
}
// The distal fragment moved about the fracture site: X = T(site + offset) · R · T(-site) · X_aligned.
Eigen::Isometry3d AboutSite(const Eigen::Isometry3d& X_aligned, const Eigen::Vector3d& site,
                            const Eigen::Vector3d& offset, const Eigen::Quaterniond& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = site + offset - T.linear() * site;
  return T * X_aligned;
}
}  // namespace

SinusoidTrajectory::SinusoidTrajectory(const Eigen::Isometry3d& X_FM_center, const SinusoidConfig& config)
    : center_(X_FM_center), config_(config) {}

Eigen::Isometry3d SinusoidTrajectory::Pose(double t) const {
  const double envelope = config_.ramp_s > 0 ? Smoothstep(t / config_.ramp_s) : 1.0;
  Vector6d s;
  for (int k = 0; k < 6; ++k) s[k] = envelope * std::sin(2.0 * kPi * t / config_.period_s[k]);
  Eigen::Isometry3d X = center_;
  X.translation() += config_.amplitude_m.cwiseProduct(s.head<3>());
  X.linear() = RotationFromRpy(config_.amplitude_rad.cwiseProduct(s.tail<3>())) * center_.linear();
  return X;
}

ReductionTrajectory::ReductionTrajectory(const Eigen::Isometry3d& X_FM_aligned, const Eigen::Vector3d& site_F,
                                         const ReductionConfig& config, double duration_s)
    : X_aligned_(X_FM_aligned), site_(site_F), config_(config), duration_s_(duration_s) {
  const Eigen::Quaterniond displaced(Eigen::AngleAxisd(config.rotation_rad, Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(config.angulation_rad, Eigen::Vector3d::UnitX()));
  offset_[0] = Eigen::Vector3d(config.lateral_m, 0, -config.shortening_m);
  offset_[1] = Eigen::Vector3d(config.lateral_m, 0, config.clearance_m);
  offset_[2] = Eigen::Vector3d(0, 0, config.clearance_m);
  offset_[3] = Eigen::Vector3d(0, 0, config.final_gap_m);
  rotation_ = {displaced, displaced, Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity()};
}

Eigen::Isometry3d ReductionTrajectory::Waypoint(int k) const {
  return AboutSite(X_aligned_, site_, offset_[k], rotation_[k]);
}

Eigen::Isometry3d ReductionTrajectory::Pose(double t) const {
  double start = 0;
  for (int phase = 0; phase < 3; ++phase) {
    const double length = config_.phase_fractions[phase] * duration_s_;
    if (t < start + length) {
      const double s = MinimumJerk((t - start) / length);
      const Eigen::Vector3d offset = offset_[phase] + s * (offset_[phase + 1] - offset_[phase]);
      return AboutSite(X_aligned_, site_, offset, rotation_[phase].slerp(s, rotation_[phase + 1]));
    }
    start += length;
  }
  return Waypoint(3);
}

Vector6d ArmGravityWrench(const robot::RsrModel& model, const MassConfig& m, const Eigen::Vector3d& g_F,
                          const Eigen::Isometry3d& X_FM) {
  auto potential = [&](const Eigen::Isometry3d& X) {
    double V = 0;
    for (int i = 0; i < robot::kNumArms; ++i) {
      const Eigen::Vector3d leg = X * model.p_MB(i) - model.p_FA(i);
      const double d = leg.norm();
      const Eigen::Vector3d n = leg / d;
      const Eigen::Vector3d p_cyl = model.p_FA(i) + m.cylinder_com_from_base_m * n;
      const Eigen::Vector3d p_piston = model.p_FA(i) + (d - m.piston_com_below_tip_m) * n;
      V -= m.cylinder_kg * g_F.dot(p_cyl) + m.piston_kg * g_F.dot(p_piston);
    }
    return V;
  };
  const double h = 1e-6;
  Vector6d W;
  for (int k = 0; k < 6; ++k) {
    Vector6d xi = Vector6d::Zero();
    xi[k] = h;
    auto perturbed = [&](double sign) {
      Eigen::Isometry3d X = X_FM;
      X.translation() += sign * xi.head<3>();
      X.linear() = RotationFromVector(sign * xi.tail<3>()) * X_FM.linear();
      return X;
    };
    W[k] = -(potential(perturbed(+1)) - potential(perturbed(-1))) / (2 * h);
  }
  return W;
}

ScenarioSetup MakeScenarioSetup(const robot::RsrModel& model, const SimConfig& config, const BoneFragments& fragments,
                                const ScenarioParams& params) {
  const Eigen::Isometry3d X_aligned = model.geometry().X_FM_home;
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  MuscleTraction traction(config.traction, axis, fragments.fracture_site_F, X_aligned);
  std::unique_ptr<PoseTrajectory> trajectory;
  if (params.kind == ScenarioKind::kSinusoid) {
    Eigen::Isometry3d center = X_aligned;
    center.translation() += config.sinusoid.center_offset_m;
    trajectory = std::make_unique<SinusoidTrajectory>(center, config.sinusoid);
    // Peak loads at the extremes: the lines at the most distracted pose, the torsion at the yaw extreme.
    Eigen::Isometry3d lines_ref = center;
    lines_ref.translation().z() += config.sinusoid.amplitude_m.z();
    const Eigen::Matrix3d twist_ref =
        Eigen::AngleAxisd(-config.sinusoid.amplitude_rad.z(), axis).toRotationMatrix() * center.linear();
    traction.Calibrate(lines_ref, twist_ref, params.load_n, params.load_nm, +1.0);
  } else {
    auto reduction = std::make_unique<ReductionTrajectory>(X_aligned, fragments.fracture_site_F, config.reduction,
                                                           params.duration_s);
    // The lines are longest at full length plus the clearance; the torsion is largest once derotated.
    traction.Calibrate(reduction->Waypoint(2), X_aligned.linear(), params.load_n, params.load_nm,
                       config.reduction.rotation_rad >= 0 ? 1.0 : -1.0);
    trajectory = std::move(reduction);
  }
  return ScenarioSetup{std::move(trajectory), std::move(traction)};
}

namespace {

// CPU time of the calling thread: the real-time factor "on one core", unaffected by other processes sharing it.
double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

robot::RsrJointVector JointsOf(const robot::RsrModel& model, const Eigen::Isometry3d& X) {
  return robot::CalcInverseKinematics(model, X).joints.actuated();
}

void CheckTrajectoryFeasible(const robot::RsrModel& model, const PoseTrajectory& trajectory, const ScenarioParams& p) {
  const double dt = 0.01;
  for (double t = 0; t <= p.duration_s + 1e-12; t += dt) {
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, trajectory.Pose(t));
    if (!ik.feasible) {
      const robot::RsrLimitCheck& worst = ik.tightest();
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "scenario '%s': the commanded pose at t = %.2f s violates the %s limit of arm %d "
                    "(check --load-n/--duration-s and the scenario settings in sim.yaml)",
                    ToString(p.kind), t, robot::ToString(worst.joint), worst.arm + 1);
      throw std::invalid_argument(buf);
    }
  }
}

}  // namespace

ScenarioResult RunScenario(const robot::RsrModel& model, const SimConfig& config, const BoneFragments& fragments,
                           const ScenarioParams& params, const std::function<void(double)>& progress) {
  ValidateScenarioParams(params, config);
  ScenarioSetup setup = MakeScenarioSetup(model, config, fragments, params);
  const PoseTrajectory& trajectory = *setup.trajectory;
  CheckTrajectoryFeasible(model, trajectory, params);

  SimOptions options;
  options.gravity = params.gravity;
  options.with_traction = params.load_n > 0 || params.load_nm > 0;
  RsrSimulation sim(model, config, &fragments, &setup.traction, trajectory.Pose(0), options);
  robot::Follower& follower = sim;  // driven only through the follower interface

  ScenarioResult result;
  result.params = params;
  ScenarioSummary& s = result.summary;
  s.penetration_tolerance_mm = MToMm(config.bone.penetration_tolerance_m);
  s.ring_mass_kg = sim.ring_mass_kg();
  const double dt = sim.step_s();
  const long steps = std::lround(params.duration_s / dt);
  const long record_every = std::max(1L, std::lround(config.physics.step_hz / params.record_hz));
  result.samples.reserve(static_cast<std::size_t>(steps / record_every + 2));
  const double h = 0.5 * dt;  // central difference of the IK for the velocity feed-forward (eq. 15)
  const Eigen::Vector3d g = params.gravity ? config.physics.gravity_F_mps2 : Eigen::Vector3d::Zero();
  const Eigen::Vector3d com_M = sim.ring_com_M();
  const double ring_mass = sim.ring_mass_kg();
  double sum_t = 0, sum_r = 0;
  double wall = 0, cpu = 0;
  const long progress_every = std::max(1L, steps / 20);

  for (long k = 1; k <= steps; ++k) {
    const double t = k * dt;
    const Eigen::Isometry3d X_cmd = trajectory.Pose(t);
    robot::RsrJointCommand command;
    command.time_s = t;
    command.q = JointsOf(model, X_cmd);
    command.q_dot = (JointsOf(model, trajectory.Pose(t + h)) - JointsOf(model, trajectory.Pose(t - h))) / (2 * h);

    const auto start = std::chrono::steady_clock::now();
    const double start_cpu = ThreadCpuSeconds();
    follower.Command(command);
    const SimStepStatus status = sim.Step();
    const robot::RsrFollowerState state = follower.State();
    cpu += ThreadCpuSeconds() - start_cpu;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const SimDiagnostics& d = sim.diagnostics();
    const double e_t = (state.X_FM.translation() - X_cmd.translation()).norm();
    const double e_r = RotationAngleBetween(state.X_FM.linear(), X_cmd.linear());
    s.max_translation_error_mm = std::max(s.max_translation_error_mm, MToMm(e_t));
    s.max_rotation_error_deg = std::max(s.max_rotation_error_deg, RadToDeg(e_r));
    sum_t += e_t;
    sum_r += e_r;
    for (int i = 0; i < robot::kNumArms; ++i) {
      s.max_actuator_torque_nm = std::max(s.max_actuator_torque_nm, std::abs(state.effort[robot::ThetaIndex(i)]));
      s.max_actuator_force_n = std::max(s.max_actuator_force_n, std::abs(state.effort[robot::StrokeIndex(i)]));
    }
    if (status == SimStepStatus::kActuatorLimit) {
      if (!s.actuator_limit_reached) {
        s.first_actuator_limit_time_s = t;
        std::ostringstream msg;
        msg << "actuator limit reached at t = " << t << " s:";
        for (int i = 0; i < robot::kNumArms; ++i) {
          if (d.linear_saturated[i]) msg << " linear drive " << i + 1 << " at " << config.actuators.linear_force_max_n << " N;";
          if (d.rotary_saturated[i]) msg << " rotary drive " << i + 1 << " at " << config.actuators.rotary_torque_max_nm << " N·m;";
        }
        s.actuator_limit_message = msg.str();
      }
      s.actuator_limit_reached = true;
      ++s.actuator_limit_steps;
    }
    s.joint_limit_reached = s.joint_limit_reached || d.joint_limit_active;
    s.max_spherical_cone_deg = std::max(s.max_spherical_cone_deg, RadToDeg(d.max_cone_rad));
    s.max_penetration_mm = std::max(s.max_penetration_mm, MToMm(d.max_penetration_m));
    if (d.contact_points > 0) ++s.contact_steps;
    s.peak_traction_n = std::max(s.peak_traction_n, std::abs(d.traction.axial_force_n));
    s.peak_traction_torque_nm = std::max(s.peak_traction_torque_nm, std::abs(d.traction.twist_torque_nm));
    s.max_loop_error_m = std::max(s.max_loop_error_m, d.max_loop_error_m);
    if (status == SimStepStatus::kUnstable) s.unstable = true;

    // Statics: the actuators balance traction + the ring's weight + the arms' weight (virtual work), Q = -J^-T W.
    robot::RsrJointVector q_stat = robot::RsrJointVector::Constant(std::nan(""));
    if (d.contact_points == 0) {
      const Eigen::Vector3d c_F = state.X_FM * com_M;
      Vector6d W = d.traction.wrench_P_F;
      W.head<3>() += ring_mass * g;
      W.tail<3>() += (c_F - state.X_FM.translation()).cross(ring_mass * g);
      W += ArmGravityWrench(model, config.masses, g, state.X_FM);
      const robot::RsrStaticsResult statics = robot::CalcActuatorEfforts(model, state.X_FM, W);
      if (!statics.singular) {
        q_stat << statics.rotary_torque_nm, statics.linear_force_n;
        const double lin_scale = std::max(statics.linear_force_n.cwiseAbs().maxCoeff(),
                                          0.01 * config.actuators.linear_force_max_n);
        const double rot_scale = std::max(statics.rotary_torque_nm.cwiseAbs().maxCoeff(),
                                          0.01 * config.actuators.rotary_torque_max_nm);
        const robot::RsrJointVector diff = state.effort - q_stat;
        s.statics_linear_rel_error = std::max(s.statics_linear_rel_error, diff.tail<3>().cwiseAbs().maxCoeff() / lin_scale);
        s.statics_rotary_rel_error = std::max(s.statics_rotary_rel_error, diff.head<3>().cwiseAbs().maxCoeff() / rot_scale);
        ++s.statics_steps;
      }
    }

    if (k % record_every == 0 || k == steps) {
      ScenarioSample row;
      row.time_s = t;
      row.pose_cmd_mm_deg = MmDegFromPose(X_cmd);
      row.pose_meas_mm_deg = MmDegFromPose(state.X_FM);
      row.translation_error_m = e_t;
      row.rotation_error_rad = e_r;
      row.q_cmd = command.q;
      row.q_meas = state.q;
      row.effort = state.effort;
      row.effort_statics = q_stat;
      row.traction_axial_n = d.traction.axial_force_n;
      row.traction_torque_nm = d.traction.twist_torque_nm;
      row.penetration_m = d.max_penetration_m;
      row.status = status;
      result.samples.push_back(row);
    }
    if (progress && k % progress_every == 0) progress(static_cast<double>(k) / steps);
  }
  s.steps = steps;
  s.simulated_s = steps * dt;
  s.wall_s = wall;
  s.cpu_s = cpu;
  s.realtime_factor = cpu > 0 ? s.simulated_s / cpu : 0;
  s.realtime_factor_wall = wall > 0 ? s.simulated_s / wall : 0;
  s.mean_translation_error_mm = MToMm(sum_t / steps);
  s.mean_rotation_error_deg = RadToDeg(sum_r / steps);
  s.spherical_limit_exceeded = s.max_spherical_cone_deg > RadToDeg(model.limits().spherical_cone_max_rad);
  return result;
}

std::string TrajectoryCsv(const ScenarioResult& result) {
  std::ostringstream os;
  os.precision(10);
  os << "time_s";
  for (const char* prefix : {"cmd", "meas"}) {
    for (const char* axis : {"x_mm", "y_mm", "z_mm", "roll_deg", "pitch_deg", "yaw_deg"}) os << "," << prefix << "_" << axis;
  }
  os << ",translation_error_mm,rotation_error_deg";
  for (const char* prefix : {"q_cmd", "q_meas"}) {
    os << "," << prefix << "_theta1_deg," << prefix << "_theta2_deg," << prefix << "_theta3_deg," << prefix
       << "_d1_mm," << prefix << "_d2_mm," << prefix << "_d3_mm";
  }
  os << ",torque1_nm,torque2_nm,torque3_nm,force1_n,force2_n,force3_n"
     << ",statics_torque1_nm,statics_torque2_nm,statics_torque3_nm,statics_force1_n,statics_force2_n,statics_force3_n"
     << ",traction_n,traction_torque_nm,penetration_mm,status\n";
  auto joints = [&](const robot::RsrJointVector& q) {
    for (int j = 0; j < 3; ++j) os << "," << RadToDeg(q[j]);
    for (int j = 3; j < 6; ++j) os << "," << MToMm(q[j]);
  };
  for (const ScenarioSample& r : result.samples) {
    os << r.time_s;
    for (int k = 0; k < 6; ++k) os << "," << r.pose_cmd_mm_deg[k];
    for (int k = 0; k < 6; ++k) os << "," << r.pose_meas_mm_deg[k];
    os << "," << MToMm(r.translation_error_m) << "," << RadToDeg(r.rotation_error_rad);
    joints(r.q_cmd);
    joints(r.q_meas);
    for (int k = 0; k < 6; ++k) os << "," << r.effort[k];
    for (int k = 0; k < 6; ++k) {
      os << ",";
      if (std::isfinite(r.effort_statics[k])) os << r.effort_statics[k];
    }
    os << "," << r.traction_axial_n << "," << r.traction_torque_nm << "," << MToMm(r.penetration_m) << ","
       << ToString(r.status) << "\n";
  }
  return os.str();
}

}  // namespace robossis::sim
