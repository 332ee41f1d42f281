#include "idto/multibody/model_builder.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Eigenvalues>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/data.hpp"

namespace idto {

namespace {

std::string Quoted(const std::string& s) { return "\"" + s + "\""; }

bool IsFinitePose(const Eigen::Isometry3d& X) { return X.matrix().allFinite(); }

bool IsRotation(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-9 &&
         R.determinant() > 0.0;
}

RigidTransform ToRigid(const Eigen::Isometry3d& X) { return {X.linear(), X.translation()}; }

// Checks mass >= 0 and a physically valid rotational inertia about the centre of mass.
void CheckInertia(const std::string& where, const std::string& body, const BodyInertia& I) {
  if (!std::isfinite(I.mass) || I.mass < 0.0) {
    ThrowInvalidArgument(where, "mass of body " + Quoted(body), FormatValue(I.mass),
                         "a finite non-negative number");
  }
  if (!I.p_BBcm.allFinite()) {
    ThrowInvalidArgument(where, "centre of mass of body " + Quoted(body), "not finite",
                         "a finite position");
  }
  if (!I.I_BBcm_B.allFinite()) {
    ThrowInvalidArgument(where, "inertia of body " + Quoted(body), "not finite",
                         "a finite symmetric matrix");
  }
  const double scale = std::max(1e-300, I.I_BBcm_B.cwiseAbs().maxCoeff());
  if ((I.I_BBcm_B - I.I_BBcm_B.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    ThrowInvalidArgument(where, "inertia of body " + Quoted(body), "not symmetric",
                         "a symmetric matrix");
  }
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I.I_BBcm_B, Eigen::EigenvaluesOnly)
          .eigenvalues();
  const double tol = 1e-9 * scale;
  if (moments.minCoeff() < -tol) {
    ThrowInvalidArgument(
        where, "inertia of body " + Quoted(body),
        "indefinite (smallest principal moment " + FormatValue(moments.minCoeff()) + ")",
        "a positive semi-definite matrix");
  }
  // Triangle inequality of principal moments (sorted ascending): largest <= sum of the others.
  if (moments(2) > moments(0) + moments(1) + tol) {
    ThrowInvalidArgument(where, "inertia of body " + Quoted(body),
                         "principal moments violating the triangle inequality (" +
                             FormatValue(moments(0)) + ", " + FormatValue(moments(1)) + ", " +
                             FormatValue(moments(2)) + ")",
                         "the largest principal moment at most the sum of the other two");
  }
}

bool JointHasAxis(JointType t) {
  return t == JointType::kRevolute || t == JointType::kContinuous || t == JointType::kPrismatic ||
         t == JointType::kPlanar;
}

// Fields of a JointSpec that its type does not use must keep their defaults: position limits
// exist for revolute and prismatic joints only, and a fixed joint has no damping, effort or
// velocity. A value there would otherwise be dropped without a word.
void CheckUnusedJointFields(const char* where, const JointSpec& spec) {
  const std::string joint = "joint " + Quoted(spec.name);
  const std::string type = JointTypeName(spec.type);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const bool has_position_limits =
      spec.type == JointType::kRevolute || spec.type == JointType::kPrismatic;
  if (!has_position_limits && (spec.lower_limit != -kInf || spec.upper_limit != kInf)) {
    ThrowInvalidArgument(
        where, "limits of " + type + " " + joint,
        "[" + FormatValue(spec.lower_limit) + ", " + FormatValue(spec.upper_limit) + "]",
        "[-inf, inf]: only revolute and prismatic joints have position limits");
  }
  if (spec.type != JointType::kFixed) return;
  auto unused = [&](const char* field, double value, double fallback) {
    if (value == fallback) return;
    ThrowInvalidArgument(where, std::string(field) + " of fixed " + joint, FormatValue(value),
                         FormatValue(fallback) + ": a fixed joint does not move");
  };
  unused("damping", spec.damping, 0.0);
  unused("effort limit", spec.effort_limit, kInf);
  unused("velocity limit", spec.velocity_limit, kInf);
}

// Every moving body must carry mass (its own, welded or moving below it), and the joint-space
// mass matrix at the neutral configuration must be positive definite. Point masses and massless
// intermediate bodies pass when the bodies they carry give every DoF inertia.
void CheckMassMatrix(const char* where, const Model& m) {
  std::vector<double> subtree_mass(static_cast<size_t>(m.num_bodies()), 0.0);
  for (BodyIndex b = m.num_bodies() - 1; b >= 1; --b) {
    subtree_mass[b] += m.body_mass(b);
    if (m.parent(b) >= 1) subtree_mass[m.parent(b)] += subtree_mass[b];
  }
  for (BodyIndex b : m.moving_bodies()) {
    if (!(subtree_mass[b] > 0.0)) {
      ThrowInvalidArgument(where, "mass of moving body " + Quoted(m.body_name(b)),
                           FormatValue(subtree_mass[b]) + " (including the bodies it carries)",
                           "a positive mass for a body on a non-fixed joint");
    }
  }
  if (m.nv() == 0) return;
  Data data(m);
  const Eigen::MatrixXd M = MassMatrix(m, m.NeutralConfiguration(), &data);
  auto joint_of = [&](int i) { return Quoted(m.velocity_name(i)); };
  const Eigen::VectorXd d = M.diagonal();
  const double largest = d.cwiseAbs().maxCoeff();
  for (int i = 0; i < m.nv(); ++i) {
    if (!(d(i) > 1e-12 * largest)) {
      ThrowInvalidArgument(where, "mass matrix at the neutral configuration",
                           "not positive definite: M(" + std::to_string(i) + ", " +
                               std::to_string(i) + ") = " + FormatValue(d(i)) + " (joint " +
                               joint_of(i) + ": what it moves has no inertia along this DoF)",
                           "a positive-definite joint-space inertia (a point mass needs a lever "
                           "arm; a free or planar body needs rotational inertia)");
    }
  }
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd S = s.asDiagonal() * M * s.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (!(eig.eigenvalues()(0) > 1e-10)) {
    Eigen::Index worst = 0;
    eig.eigenvectors().col(0).cwiseAbs().maxCoeff(&worst);
    ThrowInvalidArgument(where, "mass matrix at the neutral configuration",
                         "not positive definite (smallest eigenvalue of the Jacobi-scaled matrix " +
                             FormatValue(eig.eigenvalues()(0)) + ", mostly joint " +
                             joint_of(static_cast<int>(worst)) + ")",
                         "a positive-definite joint-space inertia");
  }
}

}  // namespace

ModelBuilder::ModelBuilder(std::string model_name) : name_(std::move(model_name)) {
  bodies_.push_back(BodyEntry{"world", -1, BodyInertia{}, JointSpec{}});
  frames_.push_back(FrameEntry{"world", kWorldBody, Eigen::Isometry3d::Identity()});
}

void ModelBuilder::SetName(const std::string& name) { name_ = name; }

void ModelBuilder::CheckNewName(const char* where, const std::string& kind,
                                const std::string& name) const {
  if (name.empty()) ThrowInvalidArgument(where, kind + " name", "empty", "a non-empty name");
  auto duplicate = [&]() {
    ThrowInvalidArgument(where, kind + " name", Quoted(name) + " (already used)",
                         "a name unique among the model's " + kind + "s");
  };
  if (kind == "body" || kind == "frame") {
    for (const FrameEntry& f : frames_) {
      if (f.name == name) duplicate();
    }
  } else if (kind == "joint") {
    for (const BodyEntry& b : bodies_) {
      if (b.parent >= 0 && b.joint.name == name) duplicate();
    }
  } else if (kind == "geometry") {
    for (const GeometryInstance& g : geometries_) {
      if (g.name == name) duplicate();
    }
  }
}

BodyIndex ModelBuilder::AddBody(const std::string& name, const BodyInertia& inertia,
                                BodyIndex parent, const JointSpec& joint) {
  static constexpr const char* kWhere = "ModelBuilder::AddBody";
  CheckNewName(kWhere, "body", name);
  CheckNewName(kWhere, "joint", joint.name);
  if (parent < 0 || parent >= num_bodies()) {
    ThrowInvalidArgument(kWhere, "parent of body " + Quoted(name), std::to_string(parent),
                         "an existing body index in [0, " + std::to_string(num_bodies()) + ")");
  }
  CheckInertia(kWhere, name, inertia);
  if (!IsFinitePose(joint.X_PJ) || !IsRotation(joint.X_PJ.linear())) {
    ThrowInvalidArgument(kWhere, "X_PJ of joint " + Quoted(joint.name),
                         "not a finite rigid transform", "a finite pose with a rotation matrix");
  }
  JointSpec spec = joint;
  if (JointHasAxis(spec.type)) {
    const double n = spec.axis.norm();
    if (!std::isfinite(n) || n < 1e-12) {
      ThrowInvalidArgument(kWhere, "axis of joint " + Quoted(joint.name),
                           "(" + FormatValue(spec.axis.x()) + ", " + FormatValue(spec.axis.y()) +
                               ", " + FormatValue(spec.axis.z()) + ")",
                           "a finite non-zero vector");
    }
    spec.axis /= n;
  }
  if (!std::isfinite(spec.damping) || spec.damping < 0.0) {
    ThrowInvalidArgument(kWhere, "damping of joint " + Quoted(joint.name),
                         FormatValue(spec.damping), "a finite non-negative number");
  }
  if (std::isnan(spec.effort_limit) || spec.effort_limit <= 0.0) {
    ThrowInvalidArgument(kWhere, "effort limit of joint " + Quoted(joint.name),
                         FormatValue(spec.effort_limit), "a positive number (or infinity)");
  }
  if (std::isnan(spec.velocity_limit) || spec.velocity_limit <= 0.0) {
    ThrowInvalidArgument(kWhere, "velocity limit of joint " + Quoted(joint.name),
                         FormatValue(spec.velocity_limit), "a positive number (or infinity)");
  }
  if (std::isnan(spec.lower_limit) || std::isnan(spec.upper_limit) ||
      spec.lower_limit > spec.upper_limit) {
    ThrowInvalidArgument(
        kWhere, "limits of joint " + Quoted(joint.name),
        "[" + FormatValue(spec.lower_limit) + ", " + FormatValue(spec.upper_limit) + "]",
        "lower <= upper");
  }
  CheckUnusedJointFields(kWhere, spec);
  bodies_.push_back(BodyEntry{name, parent, inertia, spec});
  const BodyIndex b = num_bodies() - 1;
  frames_.push_back(FrameEntry{name, b, Eigen::Isometry3d::Identity()});
  return b;
}

FrameIndex ModelBuilder::AddFrame(const std::string& name, BodyIndex body,
                                  const Eigen::Isometry3d& X_BF) {
  static constexpr const char* kWhere = "ModelBuilder::AddFrame";
  CheckNewName(kWhere, "frame", name);
  if (body < 0 || body >= num_bodies()) {
    ThrowInvalidArgument(kWhere, "body of frame " + Quoted(name), std::to_string(body),
                         "an existing body index in [0, " + std::to_string(num_bodies()) + ")");
  }
  if (!IsFinitePose(X_BF) || !IsRotation(X_BF.linear())) {
    ThrowInvalidArgument(kWhere, "X_BF of frame " + Quoted(name), "not a finite rigid transform",
                         "a finite pose with a rotation matrix");
  }
  frames_.push_back(FrameEntry{name, body, X_BF});
  return static_cast<FrameIndex>(frames_.size()) - 1;
}

GeometryIndex ModelBuilder::AddGeometry(const std::string& name, BodyIndex body,
                                        const Eigen::Isometry3d& X_BG, const Shape& shape) {
  static constexpr const char* kWhere = "ModelBuilder::AddGeometry";
  CheckNewName(kWhere, "geometry", name);
  if (body < 0 || body >= num_bodies()) {
    ThrowInvalidArgument(kWhere, "body of geometry " + Quoted(name), std::to_string(body),
                         "an existing body index in [0, " + std::to_string(num_bodies()) + ")");
  }
  if (!IsFinitePose(X_BG) || !IsRotation(X_BG.linear())) {
    ThrowInvalidArgument(kWhere, "X_BG of geometry " + Quoted(name), "not a finite rigid transform",
                         "a finite pose with a rotation matrix");
  }
  auto check_positive = [&](const char* what, double value) {
    if (!(std::isfinite(value) && value > 0.0)) {
      ThrowInvalidArgument(kWhere, std::string(what) + " of geometry " + Quoted(name),
                           FormatValue(value), "a finite positive number");
    }
  };
  if (const auto* s = std::get_if<Sphere>(&shape)) check_positive("radius", s->radius);
  if (const auto* c = std::get_if<Capsule>(&shape)) {
    check_positive("radius", c->radius);
    if (!(std::isfinite(c->length) && c->length >= 0.0)) check_positive("length", c->length);
  }
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    check_positive("radius", c->radius);
    check_positive("length", c->length);
  }
  if (const auto* bx = std::get_if<Box>(&shape)) {
    for (int i = 0; i < 3; ++i) check_positive("size", bx->size(i));
  }
  geometries_.push_back(GeometryInstance{name, body, X_BG, shape});
  return static_cast<GeometryIndex>(geometries_.size()) - 1;
}

void ModelBuilder::SetGravity(const Eigen::Vector3d& gravity) {
  if (!gravity.allFinite()) {
    ThrowInvalidArgument("ModelBuilder::SetGravity", "gravity", "not finite", "a finite vector");
  }
  gravity_ = gravity;
}

BodyIndex ModelBuilder::GetBodyIndex(const std::string& name) const {
  for (int b = 0; b < num_bodies(); ++b) {
    if (bodies_[b].name == name) return b;
  }
  ThrowInvalidArgument("ModelBuilder::GetBodyIndex", "body", Quoted(name),
                       "the name of a body added so far");
}

bool ModelBuilder::HasBody(const std::string& name) const {
  for (const BodyEntry& b : bodies_) {
    if (b.name == name) return true;
  }
  return false;
}

Model ModelBuilder::Build() const {
  static constexpr const char* kWhere = "ModelBuilder::Build";
  Model m;
  m.name_ = name_;
  m.gravity_ = gravity_;
  const int n = num_bodies();
  m.body_name_.resize(n);
  m.parent_.resize(n);
  m.mobilized_.resize(n);
  m.X_MB_.resize(n);
  m.body_inertia_.resize(n);
  m.inertia_.assign(n, SpatialInertia::Zero());
  m.joint_name_.resize(n);
  m.joint_type_.resize(n);
  m.q_start_.assign(n, 0);
  m.v_start_.assign(n, 0);
  m.X_PJ_.resize(n);
  m.axis_.resize(n);
  m.joint_damping_.assign(n, 0.0);
  m.moving_parent_.assign(n, -1);
  m.X_MJ_.resize(n);
  m.X_MJ_translation_only_.assign(n, false);
  m.planar_e1_.assign(n, Eigen::Vector3d::UnitX());
  m.planar_e2_.assign(n, Eigen::Vector3d::UnitY());
  m.moving_bodies_.clear();
  m.floating_joints_.clear();
  m.body_index_.clear();
  m.joint_index_.clear();

  int nq = 0, nv = 0;
  for (int b = 0; b < n; ++b) {
    const BodyEntry& e = bodies_[b];
    m.body_name_[b] = e.name;
    m.body_index_[e.name] = b;
    m.parent_[b] = e.parent;
    m.body_inertia_[b] = e.inertia;
    if (b == 0) {
      m.mobilized_[0] = 0;
      m.X_MB_[0] = RigidTransform::Identity();
      continue;
    }
    const JointSpec& j = e.joint;
    m.joint_name_[b] = j.name;
    m.joint_index_[j.name] = b;
    m.joint_type_[b] = j.type;
    m.X_PJ_[b] = j.X_PJ;
    m.axis_[b] = j.axis;
    m.joint_damping_[b] = j.damping;
    m.q_start_[b] = nq;
    m.v_start_[b] = nv;
    // Pose of the joint frame in the parent's moving body.
    const RigidTransform X_MJ = m.X_MB_[e.parent] * ToRigid(j.X_PJ);
    if (j.type == JointType::kFixed) {
      m.mobilized_[b] = m.mobilized_[e.parent];
      m.X_MB_[b] = X_MJ;
    } else {
      m.mobilized_[b] = b;
      m.X_MB_[b] = RigidTransform::Identity();
      m.moving_parent_[b] = m.mobilized_[e.parent];
      m.X_MJ_[b] = X_MJ;
      m.X_MJ_translation_only_[b] = X_MJ.R == Eigen::Matrix3d::Identity();
      m.moving_bodies_.push_back(b);
      if (j.type == JointType::kFloating) m.floating_joints_.push_back(b);
      if (j.type == JointType::kPlanar) {
        const Eigen::Vector3d& nrm = j.axis;
        Eigen::Vector3d e1 = Eigen::Vector3d::UnitX() - nrm.x() * nrm;
        if (e1.norm() < 1e-6) e1 = Eigen::Vector3d::UnitY() - nrm.y() * nrm;
        e1.normalize();
        m.planar_e1_[b] = e1;
        m.planar_e2_[b] = nrm.cross(e1);
      }
    }
    nq += JointNq(j.type);
    nv += JointNv(j.type);
  }
  m.nq_ = nq;
  m.nv_ = nv;

  // Merge mass properties into the moving bodies.
  for (int b = 1; b < n; ++b) {
    const BodyInertia& I = bodies_[b].inertia;
    if (I.mass == 0.0 && I.I_BBcm_B.isZero(0.0)) continue;
    const BodyIndex mb = m.mobilized_[b];
    if (mb == kWorldBody) continue;  // welded to the world: no dynamics
    const SpatialInertia I_B = SpatialInertia::FromMassComInertia(I.mass, I.p_BBcm, I.I_BBcm_B);
    m.inertia_[mb] += I_B.ExpressedIn(m.X_MB_[b]);
  }
  FillJointVectors(&m);
  FillFramesAndGeometry(&m);
  CheckMassMatrix(kWhere, m);
  return m;
}

// Whole-model vectors per coordinate: damping, limits, base DoFs, owners.
void ModelBuilder::FillJointVectors(Model* model) const {
  Model& m = *model;
  const int nq = m.nq_, nv = m.nv_;
  m.damping_ = Eigen::VectorXd::Zero(nv);
  m.effort_limits_ = Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::infinity());
  m.velocity_limits_ = Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::infinity());
  m.lower_limits_ = Eigen::VectorXd::Constant(nq, -std::numeric_limits<double>::infinity());
  m.upper_limits_ = Eigen::VectorXd::Constant(nq, std::numeric_limits<double>::infinity());
  m.is_base_velocity_.assign(nv, false);
  m.velocity_owner_.assign(nv, 0);
  m.position_owner_.assign(nq, 0);
  for (BodyIndex b : m.moving_bodies_) {
    const JointSpec& j = bodies_[b].joint;
    const int iv = m.v_start_[b], iq = m.q_start_[b];
    const int jnv = JointNv(j.type), jnq = JointNq(j.type);
    m.damping_.segment(iv, jnv).setConstant(j.damping);
    m.effort_limits_.segment(iv, jnv).setConstant(j.effort_limit);
    m.velocity_limits_.segment(iv, jnv).setConstant(j.velocity_limit);
    if (j.type == JointType::kRevolute || j.type == JointType::kPrismatic) {
      m.lower_limits_(iq) = j.lower_limit;
      m.upper_limits_(iq) = j.upper_limit;
    }
    const bool base = (j.type == JointType::kFloating || j.type == JointType::kPlanar) &&
                      m.moving_parent_[b] == kWorldBody;
    for (int k = 0; k < jnv; ++k) {
      m.is_base_velocity_[iv + k] = base;
      m.velocity_owner_[iv + k] = b;
    }
    for (int k = 0; k < jnq; ++k) m.position_owner_[iq + k] = b;
  }
}

void ModelBuilder::FillFramesAndGeometry(Model* model) const {
  Model& m = *model;
  m.frame_name_.clear();
  m.frame_body_.clear();
  m.X_BF_.clear();
  m.frame_index_.clear();
  for (const FrameEntry& f : frames_) {
    m.frame_index_[f.name] = static_cast<FrameIndex>(m.frame_name_.size());
    m.frame_name_.push_back(f.name);
    m.frame_body_.push_back(f.body);
    m.X_BF_.push_back(f.X_BF);
  }
  m.geometries_ = geometries_;
  m.geometry_index_.clear();
  for (size_t g = 0; g < geometries_.size(); ++g) {
    m.geometry_index_[geometries_[g].name] = static_cast<GeometryIndex>(g);
  }
}

Model ScaleBodyInertias(const Model& model, const std::vector<double>& scale) {
  CheckSize("ScaleBodyInertias", "scale", static_cast<Eigen::Index>(scale.size()),
            model.num_bodies(), "model.num_bodies()");
  ModelBuilder builder(model.name());
  builder.SetGravity(model.gravity());
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    CheckPositive("ScaleBodyInertias", "scale[" + std::to_string(b) + "]", scale[b]);
    BodyInertia inertia = model.body_inertia(b);
    inertia.mass *= scale[b];
    inertia.I_BBcm_B *= scale[b];
    const JointIndex j = b;
    JointSpec spec;
    spec.name = model.joint_name(j);
    spec.type = model.joint_type(j);
    spec.X_PJ = model.joint_frame_in_parent(j);
    spec.axis = model.joint_axis(j);
    spec.damping = model.joint_damping(j);
    if (model.joint_nv(j) > 0) {
      spec.effort_limit = model.effort_limits()(model.velocity_start(j));
      spec.velocity_limit = model.velocity_limits()(model.velocity_start(j));
    }
    if (model.joint_nq(j) == 1) {
      spec.lower_limit = model.position_lower_limits()(model.position_start(j));
      spec.upper_limit = model.position_upper_limits()(model.position_start(j));
    }
    builder.AddBody(model.body_name(b), inertia, model.parent(b), spec);
  }
  for (FrameIndex f = 0; f < model.num_frames(); ++f) {
    const std::string& name = model.frame_name(f);
    if (model.HasBody(name) && model.GetBodyIndex(name) == model.frame_body(f)) continue;
    builder.AddFrame(name, model.frame_body(f), model.X_BF(f));
  }
  for (const GeometryInstance& g : model.geometries()) {
    builder.AddGeometry(g.name, g.body, g.X_BG, g.shape);
  }
  return builder.Build();
}

}  // namespace idto
