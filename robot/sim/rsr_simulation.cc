#include "robot/sim/rsr_simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

// Bullet, double precision only (PkgConfig::BULLET64 defines BT_USE_DOUBLE_PRECISION); never in a header.
#include <btBulletDynamicsCommon.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyMLCPConstraintSolver.h>
#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletDynamics/Featherstone/btMultiBodyPoint2Point.h>

#include "robot/rsr_kinematics.h"

#if !defined(BT_USE_DOUBLE_PRECISION)
#error "robossis_sim must be built against bullet-float64 (BT_USE_DOUBLE_PRECISION)"
#endif
static_assert(sizeof(btScalar) == sizeof(double), "Bullet must be double precision");

namespace robossis::sim {

const char* ToString(SimStepStatus status) {
  switch (status) {
    case SimStepStatus::kOk: return "ok";
    case SimStepStatus::kActuatorLimit: return "actuator_limit";
    case SimStepStatus::kJointLimit: return "joint_limit";
    case SimStepStatus::kUnstable: return "unstable";
  }
  return "unknown";
}

namespace {

using robot::kNumArms;

// Collision groups: the fragments collide only with each other; the arms' link colliders exist only so that the
// multibody constraints get solved (DEPENDENCIES.md) and collide with nothing.
constexpr int kGroupArms = 1 << 6;
constexpr int kGroupDistal = 1 << 7;
constexpr int kGroupProximal = 1 << 8;

btVector3 Bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d Eig(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }
btTransform Bt(const Eigen::Isometry3d& X) {
  const Eigen::Matrix3d& R = X.linear();
  btMatrix3x3 m(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
  return btTransform(m, Bt(Eigen::Vector3d(X.translation())));
}
Eigen::Isometry3d Eig(const btTransform& T) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  const btMatrix3x3& m = T.getBasis();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) X.linear()(r, c) = m[r][c];
  }
  X.translation() = Eig(T.getOrigin());
  return X;
}

int ThetaLink(int arm) { return 3 * arm; }
int PsiLink(int arm) { return 3 * arm + 1; }
int PistonLink(int arm) { return 3 * arm + 2; }

Eigen::Vector3d CylinderInertia(double m, double r, double length) {
  const double across = m * (3 * r * r + length * length) / 12.0;
  return Eigen::Vector3d(across, across, 0.5 * m * r * r);
}

}  // namespace

// Every Bullet object of one simulation. Owned by unique_ptr; the destructor takes them out of the world before
// any is deleted, and deletes the world before its solver, broadphase, dispatcher and configuration.
struct RsrSimulation::Bullet {
  std::unique_ptr<btDefaultCollisionConfiguration> collision_config;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btDantzigSolver> lcp;
  std::unique_ptr<btMultiBodyConstraintSolver> solver;
  std::unique_ptr<btMultiBodyDynamicsWorld> world;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::unique_ptr<btMultiBody> arms;
  std::unique_ptr<btMultiBody> ring;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints;
  std::unique_ptr<btDefaultMotionState> proximal_motion;
  std::unique_ptr<btRigidBody> proximal;
  btMultiBodyJointMotor* motors[6] = {};  // eq. 13 order, owned by `constraints`
  btMultiBodyJointLimitConstraint* limits[6] = {};
  btMultiBodyPoint2Point* spherical[3] = {};
  btVector3 pivot_piston[3];   // spherical joint B_i in the piston link frame
  btVector3 pivot_ring[3];     // B_i in the ring's base (principal) frame
  Eigen::Isometry3d X_MB = Eigen::Isometry3d::Identity();  // ring base frame B (centre of mass, principal axes) in M
  double ring_mass = 0;

  ~Bullet() {
    if (world) {
      for (auto& c : constraints) world->removeMultiBodyConstraint(c.get());
      if (proximal) world->removeRigidBody(proximal.get());
      for (auto& c : colliders) world->removeCollisionObject(c.get());
      if (ring) world->removeMultiBody(ring.get());
      if (arms) world->removeMultiBody(arms.get());
    }
    constraints.clear();
    colliders.clear();
    proximal.reset();
    ring.reset();
    arms.reset();
    world.reset();
    solver.reset();
    lcp.reset();
    broadphase.reset();
    dispatcher.reset();
    collision_config.reset();
    shapes.clear();
  }

  btCollisionShape* Own(btCollisionShape* shape) {
    shapes.emplace_back(shape);
    return shape;
  }
  btCollisionShape* HullCompound(const std::vector<std::vector<Eigen::Vector3d>>& hulls, const Eigen::Isometry3d& X,
                                 double margin) {
    auto* compound = new btCompoundShape();
    Own(compound);
    for (const auto& points : hulls) {
      auto* hull = new btConvexHullShape();
      // The margin first: the cached AABB includes it (the default 0.04 m would inflate every AABB by 8 cm).
      hull->setMargin(margin);
      for (const Eigen::Vector3d& p : points) hull->addPoint(Bt(Eigen::Vector3d(X * p)), false);
      hull->optimizeConvexHull();  // keep only the hull's vertices: cheaper support queries
      hull->recalcLocalAabb();
      Own(hull);
      compound->addChildShape(btTransform::getIdentity(), hull);
    }
    return compound;
  }
};

RsrSimulation::RsrSimulation(const robot::RsrModel& model, const SimConfig& config, const BoneFragments* fragments,
                             const MuscleTraction* traction, const Eigen::Isometry3d& X_FM_start,
                             const SimOptions& options)
    : bullet_(std::make_unique<Bullet>()), model_(model), config_(config), options_(options) {
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, X_FM_start);
  if (!ik.feasible) {
    const robot::RsrLimitCheck& worst = ik.tightest();
    throw std::invalid_argument(std::string("simulation start pose violates the ") + robot::ToString(worst.joint) +
                                " limit of arm " + std::to_string(worst.arm + 1));
  }
  if (traction != nullptr && options.with_traction) traction_.emplace(*traction);
  if (!options.with_bone) fragments = nullptr;
  step_s_ = config.physics.step_s();
  Bullet& b = *bullet_;
  const MassConfig& ms = config.masses;

  b.collision_config = std::make_unique<btDefaultCollisionConfiguration>();
  b.dispatcher = std::make_unique<btCollisionDispatcher>(b.collision_config.get());
  b.broadphase = std::make_unique<btDbvtBroadphase>();
  if (config.physics.solver == ConstraintSolverKind::kDantzig) {
    // Direct (pivoting) solution of the constraint LCP each step; Bullet falls back to PGS if it fails.
    b.lcp = std::make_unique<btDantzigSolver>();
    b.solver = std::make_unique<btMultiBodyMLCPConstraintSolver>(b.lcp.get());
  } else {
    b.solver = std::make_unique<btMultiBodyConstraintSolver>();
  }
  b.world = std::make_unique<btMultiBodyDynamicsWorld>(b.dispatcher.get(), b.broadphase.get(), b.solver.get(),
                                                       b.collision_config.get());
  b.world->setGravity(options.gravity ? Bt(config.physics.gravity_F_mps2) : btVector3(0, 0, 0));
  btContactSolverInfo& si = b.world->getSolverInfo();
  si.m_numIterations = config.physics.solver_iterations;
  si.m_globalCfm = 0;
  si.m_leastSquaresResidualThreshold = 0;  // run every iteration: accuracy over speed

  // --- The arms: one fixed-base multibody, links [theta_i, psi_i, piston_i] per arm. Every link frame is parallel
  // to F at zero joint values; the legs then point along +z.
  b.arms = std::make_unique<btMultiBody>(3 * kNumArms, 1.0, btVector3(1, 1, 1), true, false);
  b.arms->setBaseWorldTransform(btTransform::getIdentity());
  const btQuaternion identity = btQuaternion::getIdentity();
  const double c_cyl = ms.cylinder_com_from_base_m;
  const double l_p = ms.piston_com_below_tip_m;
  for (int i = 0; i < kNumArms; ++i) {
    const double r_t = ms.rotary_link_radius_m;
    b.arms->setupRevolute(ThetaLink(i), ms.rotary_link_kg, btVector3(1, 1, 1) * (0.4 * ms.rotary_link_kg * r_t * r_t),
                          -1, identity, Bt(model.rotary_axis_F(i)), Bt(model.p_FA(i)), btVector3(0, 0, 0), true);
    b.arms->setupRevolute(PsiLink(i), ms.cylinder_kg,
                          Bt(CylinderInertia(ms.cylinder_kg, ms.link_radius_m, ms.cylinder_length_m)), ThetaLink(i),
                          identity, Bt(model.tangent_axis_F(i)), btVector3(0, 0, 0), btVector3(0, 0, c_cyl), true);
    // Prismatic: the joint value is the full leg length d_i (A_i to B_i); the piston's centre of mass is l_p below B_i.
    b.arms->setupPrismatic(PistonLink(i), ms.piston_kg,
                           Bt(CylinderInertia(ms.piston_kg, ms.link_radius_m, ms.piston_length_m)), PsiLink(i),
                           identity, btVector3(0, 0, 1), btVector3(0, 0, -c_cyl), btVector3(0, 0, -l_p), true);
    b.pivot_piston[i] = btVector3(0, 0, l_p);
  }
  b.arms->finalizeMultiDof();
  b.arms->setLinearDamping(0);
  b.arms->setAngularDamping(0);
  b.arms->setUseGyroTerm(true);
  b.arms->setCanSleep(false);
  b.arms->setMaxCoordinateVelocity(1e3);
  for (int i = 0; i < kNumArms; ++i) {
    b.arms->setJointPos(ThetaLink(i), ik.joints.theta_rad[i]);
    b.arms->setJointPos(PsiLink(i), ik.joints.psi_rad[i]);
    b.arms->setJointPos(PistonLink(i), ik.joints.d_m[i]);
  }

  // --- The moving ring with the distal fragment: a floating-base multibody whose base frame B sits at the
  // combined centre of mass on the principal axes (Featherstone takes a diagonal base inertia).
  double mass = ms.moving_ring_kg;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  const double R = ms.moving_ring_radius_m;
  Eigen::Matrix3d I_M = Eigen::Vector3d(0.5, 0.5, 1.0).asDiagonal();
  I_M *= ms.moving_ring_kg * R * R;  // thin ring about its centre P (origin of M)
  double m_frag = 0;
  Eigen::Vector3d c_frag = Eigen::Vector3d::Zero();
  if (fragments != nullptr) {
    m_frag = fragments->distal_mass_M.volume_m3 * ms.bone_density_kg_per_m3;
    c_frag = fragments->distal_mass_M.centroid;
    mass += m_frag;
    first_moment += m_frag * c_frag;
  }
  const Eigen::Vector3d com_M = first_moment / mass;
  auto shift = [](double m, const Eigen::Vector3d& r) {
    return Eigen::Matrix3d(m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose()));
  };
  Eigen::Matrix3d I_com = I_M + shift(ms.moving_ring_kg, com_M);
  if (fragments != nullptr) {
    I_com += fragments->distal_mass_M.inertia_per_density * ms.bone_density_kg_per_m3 + shift(m_frag, c_frag - com_M);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I_com);
  Eigen::Matrix3d R_MB = eig.eigenvectors();
  if (R_MB.determinant() < 0) R_MB.col(2) *= -1;
  b.X_MB.linear() = R_MB;
  b.X_MB.translation() = com_M;
  b.ring_mass = mass;
  b.ring = std::make_unique<btMultiBody>(0, mass, Bt(Eigen::Vector3d(eig.eigenvalues())), false, false);
  b.ring->finalizeMultiDof();
  b.ring->setBaseWorldTransform(Bt(Eigen::Isometry3d(X_FM_start * b.X_MB)));
  b.ring->setLinearDamping(0);
  b.ring->setAngularDamping(0);
  b.ring->setUseGyroTerm(true);
  b.ring->setCanSleep(false);
  const Eigen::Isometry3d X_BM = b.X_MB.inverse();
  for (int i = 0; i < kNumArms; ++i) b.pivot_ring[i] = Bt(Eigen::Vector3d(X_BM * model.p_MB(i)));

  b.world->addMultiBody(b.arms.get());
  b.world->addMultiBody(b.ring.get());

  // Link colliders (the arms': tiny spheres colliding with nothing; the ring's: the distal fragment's hulls).
  btCollisionShape* link_shape = b.Own(new btSphereShape(0.005));
  for (int link = 0; link < 3 * kNumArms; ++link) {
    auto col = std::make_unique<btMultiBodyLinkCollider>(b.arms.get(), link);
    col->setCollisionShape(link_shape);
    b.world->addCollisionObject(col.get(), kGroupArms, 0);
    b.arms->getLink(link).m_collider = col.get();
    b.colliders.push_back(std::move(col));
  }
  {
    auto col = std::make_unique<btMultiBodyLinkCollider>(b.ring.get(), -1);
    if (fragments != nullptr) {
      col->setCollisionShape(b.HullCompound(fragments->distal_hulls_M, X_BM, config.bone.collision_margin_m));
      b.world->addCollisionObject(col.get(), kGroupDistal, kGroupProximal);
    } else {
      col->setCollisionShape(link_shape);
      b.world->addCollisionObject(col.get(), kGroupArms, 0);
    }
    b.ring->setBaseCollider(col.get());
    b.colliders.push_back(std::move(col));
  }
  if (fragments != nullptr) {
    btCollisionShape* shape =
        b.HullCompound(fragments->proximal_hulls_F, Eigen::Isometry3d::Identity(), config.bone.collision_margin_m);
    b.proximal_motion = std::make_unique<btDefaultMotionState>(btTransform::getIdentity());
    btRigidBody::btRigidBodyConstructionInfo info(0.0, b.proximal_motion.get(), shape, btVector3(0, 0, 0));
    b.proximal = std::make_unique<btRigidBody>(info);
    b.world->addRigidBody(b.proximal.get(), kGroupProximal, kGroupDistal);
  }

  // Loop closure: the spherical joints B_i as point-to-point constraints between each piston and the ring.
  for (int i = 0; i < kNumArms; ++i) {
    auto p2p = std::make_unique<btMultiBodyPoint2Point>(b.arms.get(), PistonLink(i), b.ring.get(), -1,
                                                        b.pivot_piston[i], b.pivot_ring[i]);
    p2p->setMaxAppliedImpulse(1e6);
    b.spherical[i] = p2p.get();
    b.world->addMultiBodyConstraint(p2p.get());
    b.constraints.push_back(std::move(p2p));
  }
  // Drives (eq. 13 order) and end stops.
  for (int j = 0; j < 6; ++j) {
    const bool rotary = j < kNumArms;
    const int arm = rotary ? j : j - kNumArms;
    const int link = rotary ? ThetaLink(arm) : PistonLink(arm);
    const double limit = rotary ? config.actuators.rotary_torque_max_nm : config.actuators.linear_force_max_n;
    auto motor = std::make_unique<btMultiBodyJointMotor>(b.arms.get(), link, 0.0, limit * step_s_);
    motor->setErp(1.0);
    motor->setRhsClamp(SIMD_INFINITY);
    b.motors[j] = motor.get();
    b.world->addMultiBodyConstraint(motor.get());
    b.constraints.push_back(std::move(motor));
    const double lo = rotary ? -model.limits().rotary_max_rad : model.limits().stroke_min_m;
    const double hi = rotary ? model.limits().rotary_max_rad : model.limits().stroke_max_m;
    auto stop = std::make_unique<btMultiBodyJointLimitConstraint>(b.arms.get(), link, lo, hi);
    stop->setMaxAppliedImpulse(1e6);
    b.limits[j] = stop.get();
    b.world->addMultiBodyConstraint(stop.get());
    b.constraints.push_back(std::move(stop));
  }

  btAlignedObjectArray<btQuaternion> scratch_q;
  btAlignedObjectArray<btVector3> scratch_m;
  b.arms->forwardKinematics(scratch_q, scratch_m);
  b.arms->updateCollisionObjectWorldTransforms(scratch_q, scratch_m);
  b.ring->forwardKinematics(scratch_q, scratch_m);
  b.ring->updateCollisionObjectWorldTransforms(scratch_q, scratch_m);

  // The Bullet chain must reproduce the kinematics (eq. 5–8): every piston tip on its B_i.
  for (int i = 0; i < kNumArms; ++i) {
    const Eigen::Vector3d tip = Eig(b.arms->localPosToWorld(PistonLink(i), b.pivot_piston[i]));
    const Eigen::Vector3d B = X_FM_start * model.p_MB(i);
    if ((tip - B).norm() > 1e-9) {
      throw std::runtime_error("Bullet RSR model: arm " + std::to_string(i + 1) + " tip is " +
                               std::to_string((tip - B).norm()) + " m from its spherical joint at the start pose");
    }
  }
  command_.time_s = 0;
  command_.q = ik.joints.actuated();
  command_.q_dot.setZero();
  target_ = command_;
  state_.enabled = true;
  state_.homed = true;
  Measure();
}

RsrSimulation::~RsrSimulation() = default;

double RsrSimulation::ring_mass_kg() const { return bullet_->ring_mass; }
Eigen::Vector3d RsrSimulation::ring_com_M() const { return bullet_->X_MB.translation(); }

bool RsrSimulation::Enable() noexcept {
  if (state_.faulted()) return false;  // robot::Follower: refused while a fault is latched (ResetFault first)
  state_.enabled = true;
  return true;
}

void RsrSimulation::Disable() noexcept {
  state_.enabled = false;
  command_.time_s = time_s_;
  command_.q = state_.q;
  command_.q_dot.setZero();
  target_ = command_;
}

bool RsrSimulation::ResetFault() noexcept {
  if (state_.fault == robot::FollowerFault::kUnstable) return false;
  state_.fault = robot::FollowerFault::kNone;
  return true;
}

void RsrSimulation::Command(const robot::RsrJointCommand& command) noexcept {
  if (!state_.enabled) return;
  if (command.q.allFinite() && command.q_dot.allFinite() && std::isfinite(command.time_s)) command_ = command;
}

void RsrSimulation::Service(double now_s) noexcept {
  // Steps whose end is due by now_s, never one that ends later: the drives' target for an instant still ahead
  // would be the newest command extrapolated, and a controller that is late itself (its command older than the
  // extrapolation's bound by then, though not by the time its next tick moves over) would find the robot held short
  // of its path, then taken back to it in one step above the speed cap. A fault in any of the steps is the call's
  // fault, though later steps may be clean: several steps in one call must not hide one.
  robot::FollowerFault first = robot::FollowerFault::kNone;
  while (time_s_ + step_s_ <= now_s + kStepDueToleranceS) {
    const SimStepStatus status = Step();
    if (first == robot::FollowerFault::kNone) first = state_.fault;
    if (status == SimStepStatus::kUnstable) break;
  }
  if (first != robot::FollowerFault::kNone) state_.fault = first;
}

void RsrSimulation::SkipTo(double time_s) noexcept {
  if (!(time_s > time_s_)) return;
  time_s_ = time_s;
  state_.time_s = time_s;
  target_.time_s = time_s;
}

robot::RsrFollowerState RsrSimulation::State() const noexcept { return state_; }

robot::RsrJointCommand RsrSimulation::DriveTargetAt(double t_s) const noexcept {
  robot::RsrJointCommand target;
  target.time_s = t_s;
  if (command_.time_s > t_s && target_.time_s < t_s) {
    // The newest command is from after this step's end: the physics runs behind the commands (a late step, caught
    // up). The drives then follow the path between the target they had and that command, at the times the
    // commands were given, rather than reaching for the newest one in one step.
    const double span = command_.time_s - target_.time_s;
    const double a = (t_s - target_.time_s) / span;
    target.q = target_.q + a * (command_.q - target_.q);
    target.q_dot = (command_.q - target_.q) / span;
    return target;
  }
  const double ahead = std::clamp(t_s - command_.time_s, 0.0, config_.physics.command_extrapolation_max_s);
  target.q = command_.q + command_.q_dot * ahead;
  target.q_dot = command_.q_dot;
  return target;
}

SimStepStatus RsrSimulation::Step() noexcept {
  Bullet& b = *bullet_;
  const double t_end = time_s_ + step_s_;
  target_ = DriveTargetAt(t_end);
  for (int j = 0; j < 6; ++j) {
    if (config_.actuators.mode == DriveMode::kPosition) {
      // rhs = kp·erp·(q* − q)/dt + q̇ + kd·(0 − q̇) = (q* − q)/dt: the drive reaches q* at the end of the step.
      b.motors[j]->setPositionTarget(target_.q[j], 1.0);
      b.motors[j]->setVelocityTarget(0.0, 1.0);
    } else {
      b.motors[j]->setPositionTarget(0.0, 0.0);
      b.motors[j]->setVelocityTarget(target_.q_dot[j], 1.0);
    }
  }
  // Muscle traction from the state at the start of the step (explicit), applied at the ring's centre of mass.
  diagnostics_.traction = TractionSample{};
  if (traction_) {
    diagnostics_.traction = traction_->Evaluate(state_.X_FM, diagnostics_.v_P_F, diagnostics_.w_F);
    const Eigen::Vector3d f = diagnostics_.traction.wrench_P_F.head<3>();
    const Eigen::Vector3d m_P = diagnostics_.traction.wrench_P_F.tail<3>();
    const Eigen::Vector3d p = state_.X_FM.translation();
    const Eigen::Vector3d c = state_.X_FM * b.X_MB.translation();
    b.ring->addBaseForce(Bt(f));
    b.ring->addBaseTorque(Bt(Eigen::Vector3d(m_P + (p - c).cross(f))));
  }
  b.world->stepSimulation(step_s_, 0, step_s_);
  time_s_ = t_end;
  Measure();
  SimStepStatus status = SimStepStatus::kOk;
  if (diagnostics_.joint_limit_active) status = SimStepStatus::kJointLimit;
  for (int i = 0; i < kNumArms; ++i) {
    if (diagnostics_.linear_saturated[i] || diagnostics_.rotary_saturated[i]) status = SimStepStatus::kActuatorLimit;
  }
  if (!state_.X_FM.matrix().allFinite() || !state_.q.allFinite() || diagnostics_.max_loop_error_m > 1e-3) {
    status = SimStepStatus::kUnstable;
  }
  switch (status) {
    case SimStepStatus::kOk: state_.fault = robot::FollowerFault::kNone; break;
    case SimStepStatus::kActuatorLimit: state_.fault = robot::FollowerFault::kDrive; break;
    case SimStepStatus::kJointLimit: state_.fault = robot::FollowerFault::kJointLimit; break;
    case SimStepStatus::kUnstable: state_.fault = robot::FollowerFault::kUnstable; break;
  }
  return status;
}

void RsrSimulation::Measure() noexcept {
  Bullet& b = *bullet_;
  state_.time_s = time_s_;
  diagnostics_.time_s = time_s_;
  for (int i = 0; i < kNumArms; ++i) {
    state_.q[robot::ThetaIndex(i)] = b.arms->getJointPos(ThetaLink(i));
    state_.q[robot::StrokeIndex(i)] = b.arms->getJointPos(PistonLink(i));
  }
  const Eigen::Isometry3d X_FB = Eig(b.ring->getBaseWorldTransform());
  state_.X_FM = X_FB * b.X_MB.inverse();
  const Eigen::Vector3d c = X_FB.translation();
  diagnostics_.w_F = Eig(b.ring->getBaseOmega());
  diagnostics_.v_P_F = Eig(b.ring->getBaseVel()) + diagnostics_.w_F.cross(state_.X_FM.translation() - c);
  diagnostics_.joint_limit_active = false;
  for (int j = 0; j < 6; ++j) {
    const double impulse = time_s_ > 0 ? b.motors[j]->getAppliedImpulse(0) : 0.0;
    state_.effort[j] = impulse / step_s_;
    const bool saturated = std::abs(impulse) >= b.motors[j]->getMaxAppliedImpulse() * (1.0 - 1e-9);
    (j < kNumArms ? diagnostics_.rotary_saturated[j] : diagnostics_.linear_saturated[j - kNumArms]) = saturated;
    if (time_s_ > 0 && b.limits[j]->getAppliedImpulse(0) != 0.0) diagnostics_.joint_limit_active = true;
  }
  diagnostics_.max_loop_error_m = 0;
  diagnostics_.max_cone_rad = 0;
  const Eigen::Vector3d z_M = state_.X_FM.linear().col(2);
  for (int i = 0; i < kNumArms; ++i) {
    const Eigen::Vector3d tip = Eig(b.arms->localPosToWorld(PistonLink(i), b.pivot_piston[i]));
    const Eigen::Vector3d B = X_FB * Eig(b.pivot_ring[i]);
    diagnostics_.max_loop_error_m = std::max(diagnostics_.max_loop_error_m, (tip - B).norm());
    const Eigen::Vector3d leg = (tip - model_.p_FA(i)).normalized();
    diagnostics_.max_cone_rad = std::max(diagnostics_.max_cone_rad, std::acos(std::clamp(leg.dot(z_M), -1.0, 1.0)));
  }
  diagnostics_.max_penetration_m = 0;
  diagnostics_.contact_points = 0;
  diagnostics_.contact_loaded = false;
  const int manifolds = b.dispatcher->getNumManifolds();
  for (int k = 0; k < manifolds; ++k) {
    const btPersistentManifold* m = b.dispatcher->getManifoldByIndexInternal(k);
    for (int c2 = 0; c2 < m->getNumContacts(); ++c2) {
      const double d = m->getContactPoint(c2).getDistance();
      if (d < 0) {
        ++diagnostics_.contact_points;
        diagnostics_.max_penetration_m = std::max(diagnostics_.max_penetration_m, -d);
      }
      if (d < 0 || m->getContactPoint(c2).getAppliedImpulse() != 0) diagnostics_.contact_loaded = true;
    }
  }
  // The true external wrench of this measurement: what the muscles applied over the step that made it (Step(): at
  // the pose and velocity that step started from; none before the first step), the load the efforts above held.
  // Gravity is not external. The fragments' contact is the one external load the simulation does not set itself (the
  // solver's impulses): a step in which it carried load leaves the true wrench unknown rather than short of it.
  state_.true_wrench_F = diagnostics_.traction.wrench_P_F;
  state_.true_wrench_known = !diagnostics_.contact_loaded;
}

}  // namespace robossis::sim
