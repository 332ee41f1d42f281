#include "idto/sim/mjcf.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Eigenvalues>

#include "idto/core/errors.hpp"

namespace idto {
namespace {

// ---------------------------------------------------------------------------------------------
// Topology shared by MakeMjcf and MujocoMap.

// The MuJoCo view of an idto model: every moving body is a MuJoCo body; welded bodies are
// carried by their moving ancestor ("mobilizer", 0 = world) at a fixed pose.
struct Tree {
  std::vector<BodyIndex> mob;                    // per body: moving ancestor (0 = world)
  std::vector<Eigen::Isometry3d> X_MB;           // per body: pose in mob
  std::vector<std::vector<BodyIndex>> children;  // per body: moving children (index order)
  std::vector<BodyIndex> dfs;                    // moving bodies in MuJoCo (depth-first) order
};

bool IsMoving(const Model& model, BodyIndex b) {
  return b != kWorldBody && model.joint_type(b) != JointType::kFixed;
}

Tree MakeTree(const Model& model) {
  const int n = model.num_bodies();
  Tree tree;
  tree.mob.assign(n, kWorldBody);
  tree.X_MB.assign(n, Eigen::Isometry3d::Identity());
  tree.children.resize(n);
  for (BodyIndex b = 1; b < n; ++b) {
    const BodyIndex p = model.parent(b);
    if (IsMoving(model, b)) {
      tree.mob[b] = b;
      tree.children[tree.mob[p]].push_back(b);
    } else {
      tree.mob[b] = tree.mob[p];
      tree.X_MB[b] = tree.X_MB[p] * model.joint_frame_in_parent(b);
    }
  }
  // Depth-first pre-order, children in index order: the order MuJoCo numbers bodies and joints.
  std::vector<BodyIndex> stack(tree.children[kWorldBody].rbegin(),
                               tree.children[kWorldBody].rend());
  while (!stack.empty()) {
    const BodyIndex b = stack.back();
    stack.pop_back();
    tree.dfs.push_back(b);
    stack.insert(stack.end(), tree.children[b].rbegin(), tree.children[b].rend());
  }
  return tree;
}

// Pose of the joint frame J of moving body b in the frame of its MuJoCo parent body.
Eigen::Isometry3d JointFrameInMujocoParent(const Model& model, const Tree& tree, BodyIndex b) {
  return tree.X_MB[model.parent(b)] * model.joint_frame_in_parent(b);
}

// A floating joint directly below the world (possibly through welded bodies) is a MuJoCo free
// joint; deeper ones become three slides and a ball.
bool IsFreeJoint(const Model& model, const Tree& tree, BodyIndex b) {
  return model.joint_type(b) == JointType::kFloating && tree.mob[model.parent(b)] == kWorldBody;
}

// Unit quaternion (w, x, y, z) stored at q.
Eigen::Quaterniond QuaternionAt(const double* q) {
  Eigen::Quaterniond Q(q[0], q[1], q[2], q[3]);
  const double n = Q.norm();
  if (n > 0.0) Q.coeffs() /= n;
  return Q;
}

// ---------------------------------------------------------------------------------------------
// Text output.

// Shortest of 15..17 significant digits that reads back exactly.
std::string Num(double x) {
  if (x == 0.0) return "0";
  char buffer[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", precision, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  return buffer;
}

template <typename Derived>
std::string Nums(const Eigen::MatrixBase<Derived>& x) {
  std::string out;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (i > 0) out += ' ';
    out += Num(x(i));
  }
  return out;
}

std::string QuatText(const Eigen::Quaterniond& Q) {
  return Nums(Eigen::Vector4d(Q.w(), Q.x(), Q.y(), Q.z()));
}

std::string Escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// pos="..." quat="..." of a pose, omitting identity parts.
std::string PoseAttributes(const Eigen::Isometry3d& X) {
  std::string out;
  if (!X.translation().isZero(0.0)) out += " pos=\"" + Nums(X.translation()) + "\"";
  if (!X.linear().isIdentity(0.0)) {
    out += " quat=\"" + QuatText(Eigen::Quaterniond(X.linear())) + "\"";
  }
  return out;
}

std::string Indent(int depth) { return std::string(2 * static_cast<std::size_t>(depth), ' '); }

// Mass, centre of mass (in M) and rotational inertia about it (in M) of moving body m, with the
// bodies welded to it.
struct MergedInertia {
  double mass{0.0};
  Eigen::Vector3d com{Eigen::Vector3d::Zero()};
  Eigen::Matrix3d I{Eigen::Matrix3d::Zero()};
};

MergedInertia MergeInertia(const Model& model, const Tree& tree, BodyIndex m) {
  MergedInertia out;
  std::vector<BodyIndex> members;
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    if (tree.mob[b] == m && model.body_inertia(b).mass > 0.0) members.push_back(b);
  }
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (const BodyIndex b : members) {
    const BodyInertia& inertia = model.body_inertia(b);
    out.mass += inertia.mass;
    first_moment += inertia.mass * (tree.X_MB[b] * inertia.p_BBcm);
  }
  if (out.mass > 0.0) out.com = first_moment / out.mass;
  for (const BodyIndex b : members) {
    const BodyInertia& inertia = model.body_inertia(b);
    const Eigen::Matrix3d R = tree.X_MB[b].linear();
    const Eigen::Vector3d d = tree.X_MB[b] * inertia.p_BBcm - out.com;
    out.I += R * inertia.I_BBcm_B * R.transpose() +
             inertia.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  out.I = 0.5 * (out.I + out.I.transpose()).eval();
  return out;
}

std::string InertialElement(const MergedInertia& inertia, bool diagonalize) {
  std::string out =
      "<inertial pos=\"" + Nums(inertia.com) + "\" mass=\"" + Num(inertia.mass) + "\"";
  const Eigen::Matrix3d& I = inertia.I;
  const bool diagonal = I(0, 1) == 0.0 && I(0, 2) == 0.0 && I(1, 2) == 0.0;
  if (diagonal) {
    out += " diaginertia=\"" + Nums(I.diagonal()) + "\"";
  } else if (diagonalize) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(I);
    Eigen::Matrix3d V = solver.eigenvectors();  // principal axes (columns) in M
    if (V.determinant() < 0.0) V.col(2) = -V.col(2);
    out += " quat=\"" + QuatText(Eigen::Quaterniond(V)) + "\"";
    out += " diaginertia=\"" + Nums(solver.eigenvalues()) + "\"";
  } else {
    out += " fullinertia=\"" +
           Nums(Eigen::Matrix<double, 6, 1>(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2))) +
           "\"";
  }
  return out + "/>";
}

std::string GeomElement(const GeometryInstance& geometry, const Eigen::Isometry3d& X_MG,
                        bool on_moving_body, const MjcfOptions& options) {
  std::string type;
  std::string size;
  std::visit(
      [&](const auto& shape) {
        using T = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<T, Sphere>) {
          type = "sphere";
          size = Num(shape.radius);
        } else if constexpr (std::is_same_v<T, Capsule>) {
          type = "capsule";
          size = Num(shape.radius) + " " + Num(0.5 * shape.length);
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          type = "cylinder";
          size = Num(shape.radius) + " " + Num(0.5 * shape.length);
        } else if constexpr (std::is_same_v<T, Box>) {
          type = "box";
          size = Nums(0.5 * shape.size);
        } else {
          type = "plane";
          size = "0 0 1";
        }
      },
      geometry.shape);
  if (type == "plane" && on_moving_body) {
    ThrowInvalidArgument("MakeMjcf", "geometry '" + geometry.name + "'",
                         "a half-space on a moving body",
                         "half-spaces only on the world or bodies welded to it (MuJoCo planes "
                         "must be static)");
  }
  return "<geom name=\"" + Escape(geometry.name) + "\" type=\"" + type + "\" size=\"" + size +
         "\"" + PoseAttributes(X_MG) + " contype=\"" + std::to_string(options.contype) +
         "\" conaffinity=\"" + std::to_string(options.conaffinity) + "\"/>";
}

std::string SiteElement(const std::string& name, const Eigen::Isometry3d& X_MS) {
  return "<site name=\"" + Escape(name) + "\"" + PoseAttributes(X_MS) + " size=\"0.005\"/>";
}

// The contents of MuJoCo body m (the world for m = 0): geoms and sites of every idto body it
// carries.
void WriteAttachments(const Model& model, const Tree& tree, BodyIndex m, const MjcfOptions& options,
                      int depth, std::ostringstream* out) {
  if (options.include_geometry) {
    for (const GeometryInstance& geometry : model.geometries()) {
      if (tree.mob[geometry.body] != m) continue;
      *out << Indent(depth)
           << GeomElement(geometry, tree.X_MB[geometry.body] * geometry.X_BG, m != kWorldBody,
                          options)
           << "\n";
    }
  }
  if (options.include_sites) {
    for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
      if (tree.mob[b] == m && b != m) {
        *out << Indent(depth) << SiteElement(model.body_name(b), tree.X_MB[b]) << "\n";
      }
    }
    for (FrameIndex f = 0; f < model.num_frames(); ++f) {
      const BodyIndex b = model.frame_body(f);
      if (tree.mob[b] != m || model.frame_name(f) == model.body_name(b)) continue;
      *out << Indent(depth) << SiteElement(model.frame_name(f), tree.X_MB[b] * model.X_BF(f))
           << "\n";
    }
  }
}

std::string JointElement(const std::string& name, const char* type, const Eigen::Vector3d* axis,
                         double damping) {
  std::string out = "<joint name=\"" + Escape(name) + "\" type=\"" + type + "\"";
  if (axis != nullptr) out += " axis=\"" + Nums(*axis) + "\"";
  if (damping != 0.0) out += " damping=\"" + Num(damping) + "\"";
  return out;
}

void WriteJoints(const Model& model, const Tree& tree, BodyIndex b, const MjcfOptions& options,
                 int depth, std::ostringstream* out) {
  const std::string& name = model.joint_name(b);
  const int iq = model.position_start(b);
  const int iv = model.velocity_start(b);
  const Eigen::VectorXd& damping = model.damping();
  const std::string pad = Indent(depth);
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous:
    case JointType::kPrismatic: {
      const bool slide = model.joint_type(b) == JointType::kPrismatic;
      *out << pad
           << JointElement(name, slide ? "slide" : "hinge", &model.joint_axis(b), damping(iv));
      const double lower = model.lower_position_limits()(iq);
      const double upper = model.upper_position_limits()(iq);
      if (options.include_joint_limits && model.joint_type(b) != JointType::kContinuous &&
          std::isfinite(lower) && std::isfinite(upper)) {
        *out << " limited=\"true\" range=\"" << Num(lower) << " " << Num(upper) << "\"";
      }
      *out << "/>\n";
      return;
    }
    case JointType::kPlanar: {
      *out << pad << JointElement(name + "_x", "slide", &model.planar_e1(b), damping(iv)) << "/>\n";
      *out << pad << JointElement(name + "_y", "slide", &model.planar_e2(b), damping(iv + 1))
           << "/>\n";
      *out << pad << JointElement(name + "_theta", "hinge", &model.joint_axis(b), damping(iv + 2))
           << "/>\n";
      return;
    }
    case JointType::kFloating: {
      if (IsFreeJoint(model, tree, b)) {
        // MuJoCo has one damping per joint; idto's is the same on every DoF of a joint.
        *out << pad << JointElement(name, "free", nullptr, damping(iv)) << "/>\n";
      } else {
        const char* suffix[3] = {"_x", "_y", "_z"};
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d axis = Eigen::Vector3d::Unit(k);
          *out << pad << JointElement(name + suffix[k], "slide", &axis, damping(iv + 3 + k))
               << "/>\n";
        }
        *out << pad << JointElement(name + "_ball", "ball", nullptr, damping(iv)) << "/>\n";
      }
      return;
    }
    case JointType::kFixed:
      return;
  }
}

void WriteBody(const Model& model, const Tree& tree, BodyIndex b, const MjcfOptions& options,
               int depth, std::ostringstream* out) {
  const std::string pad = Indent(depth);
  *out << pad << "<body name=\"" << Escape(model.body_name(b)) << "\""
       << PoseAttributes(JointFrameInMujocoParent(model, tree, b)) << ">\n";
  *out << Indent(depth + 1)
       << InertialElement(MergeInertia(model, tree, b), options.diagonalize_inertia) << "\n";
  WriteJoints(model, tree, b, options, depth + 1, out);
  WriteAttachments(model, tree, b, options, depth + 1, out);
  for (const BodyIndex child : tree.children[b]) {
    WriteBody(model, tree, child, options, depth + 1, out);
  }
  *out << pad << "</body>\n";
}

bool IsKnownIntegrator(const std::string& name) {
  return name == "Euler" || name == "RK4" || name == "implicit";
}

bool IsKnownCone(const std::string& name) { return name == "pyramidal" || name == "elliptic"; }

}  // namespace

// -----------------------------------------------------------------------------------------------

bool MjcfOptions::IsValid(std::string* why) const {
  std::string reason;
  if (!(std::isfinite(timestep) && timestep > 0.0)) {
    reason = "timestep is " + FormatValue(timestep) + "; expected a finite positive number";
  } else if (!IsKnownIntegrator(integrator)) {
    reason = "integrator is '" + integrator + "'; expected \"Euler\", \"RK4\" or \"implicit\"";
  } else if (!IsKnownCone(cone)) {
    reason = "cone is '" + cone + "'; expected \"pyramidal\" or \"elliptic\"";
  } else if (contype < 0 || conaffinity < 0) {
    reason = "contype/conaffinity are " + std::to_string(contype) + "/" +
             std::to_string(conaffinity) + "; expected non-negative bit masks";
  } else if (!contact_pairs.empty() && !include_geometry) {
    reason =
        "contact_pairs is not empty while include_geometry is false; expected geometry "
        "for the pairs";
  }
  for (size_t i = 0; i < contact_pairs.size() && reason.empty(); ++i) {
    const MjcfContactPair& pair = contact_pairs[i];
    const std::pair<const char*, double> coefficients[] = {
        {"friction_coefficient", pair.friction_coefficient},
        {"torsional_friction", pair.torsional_friction},
        {"rolling_friction", pair.rolling_friction}};
    for (const auto& [name, value] : coefficients) {
      if (!(std::isfinite(value) && value >= 0.0)) {
        reason = "contact_pairs[" + std::to_string(i) + "]." + name + " is " + FormatValue(value) +
                 "; expected a finite non-negative number";
        break;
      }
    }
  }
  if (why != nullptr) *why = reason;
  return reason.empty();
}

std::string MakeMjcf(const Model& model, const MjcfOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) {
    ThrowInvalidArgument("MakeMjcf", "options", "invalid (" + why + ")", "valid MjcfOptions");
  }
  const Tree tree = MakeTree(model);
  std::ostringstream out;
  const std::string name = options.model_name.empty() ? model.name() : options.model_name;
  out << "<mujoco model=\"" << Escape(name) << "\">\n";
  out << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
  out << "  <option timestep=\"" << Num(options.timestep) << "\" gravity=\""
      << Nums(model.gravity()) << "\" integrator=\"" << options.integrator << "\"";
  if (options.cone != "pyramidal") out << " cone=\"" << options.cone << "\"";
  if (options.disable_contact) {
    out << ">\n    <flag contact=\"disable\"/>\n  </option>\n";
  } else {
    out << "/>\n";
  }
  out << "  <worldbody>\n";
  WriteAttachments(model, tree, kWorldBody, options, 2, &out);
  for (const BodyIndex child : tree.children[kWorldBody]) {
    WriteBody(model, tree, child, options, 2, &out);
  }
  out << "  </worldbody>\n";
  if (!options.contact_pairs.empty()) {
    const int num_geometries = static_cast<int>(model.geometries().size());
    out << "  <contact>\n";
    for (size_t i = 0; i < options.contact_pairs.size(); ++i) {
      const MjcfContactPair& pair = options.contact_pairs[i];
      for (const GeometryIndex g : {pair.geometry_a, pair.geometry_b}) {
        if (g < 0 || g >= num_geometries) {
          ThrowInvalidArgument("MakeMjcf", "options.contact_pairs[" + std::to_string(i) + "]",
                               "geometry index " + std::to_string(g),
                               "an index in [0, " + std::to_string(num_geometries) + ")");
        }
      }
      const std::string mu = Num(pair.friction_coefficient);
      const int condim = pair.condim();
      // At condim 3 MuJoCo's defaults fill the unused torsional and rolling entries.
      const std::string torsional = condim == 3 ? "0.005" : Num(pair.torsional_friction);
      const std::string rolling = condim == 6 ? Num(pair.rolling_friction) : "0.0001";
      out << "    <pair geom1=\"" << Escape(model.geometries()[pair.geometry_a].name)
          << "\" geom2=\"" << Escape(model.geometries()[pair.geometry_b].name) << "\" condim=\""
          << condim << "\" friction=\"" << mu << " " << mu << " " << torsional << " " << rolling
          << " " << rolling << "\"/>\n";
    }
    out << "  </contact>\n";
  }
  if (options.include_actuators) {
    std::ostringstream actuators;
    for (const BodyIndex b : tree.dfs) {
      const JointType type = model.joint_type(b);
      if (type != JointType::kRevolute && type != JointType::kContinuous &&
          type != JointType::kPrismatic) {
        continue;
      }
      const std::string joint = Escape(model.joint_name(b));
      actuators << "    <motor name=\"" << joint << "\" joint=\"" << joint << "\" gear=\"1\"";
      const double effort = model.effort_limits()(model.velocity_start(b));
      if (std::isfinite(effort)) {
        actuators << " ctrllimited=\"true\" ctrlrange=\"" << Num(-effort) << " " << Num(effort)
                  << "\"";
      }
      actuators << "/>\n";
    }
    if (!actuators.str().empty()) out << "  <actuator>\n" << actuators.str() << "  </actuator>\n";
  }
  out << "</mujoco>\n";
  return out.str();
}

// -----------------------------------------------------------------------------------------------
// MujocoMap

MujocoMap::MujocoMap(const Model& model) : nq_(model.nq()), nv_(model.nv()) {
  const Tree tree = MakeTree(model);
  const int n = model.num_bodies();
  kind_.assign(n, Kind::kNone);
  q_start_.assign(n, 0);
  v_start_.assign(n, 0);
  mj_q_start_.assign(n, 0);
  mj_v_start_.assign(n, 0);
  X_WJ_.assign(n, Eigen::Isometry3d::Identity());
  X_MB_ = tree.X_MB;
  mj_body_id_.assign(n, 0);
  mj_body_to_idto_.assign(1, kWorldBody);
  int mq = 0;
  int mv = 0;
  for (const BodyIndex b : tree.dfs) {
    mj_body_id_[b] = static_cast<int>(mj_body_to_idto_.size());
    mj_body_to_idto_.push_back(b);
    q_start_[b] = model.position_start(b);
    v_start_[b] = model.velocity_start(b);
    mj_q_start_[b] = mq;
    mj_v_start_[b] = mv;
    mq += model.joint_nq(b);
    mv += model.joint_nv(b);
    switch (model.joint_type(b)) {
      case JointType::kPlanar:
        kind_[b] = Kind::kPlanar;
        break;
      case JointType::kFloating:
        kind_[b] = IsFreeJoint(model, tree, b) ? Kind::kFree : Kind::kNestedFloating;
        X_WJ_[b] = JointFrameInMujocoParent(model, tree, b);
        break;
      default:
        kind_[b] = Kind::kScalar;
        break;
    }
  }
  for (BodyIndex b = 1; b < n; ++b) mj_body_id_[b] = mj_body_id_[tree.mob[b]];
  for (BodyIndex b = 1; b < n; ++b) {
    if (IsMoving(model, b)) joints_.push_back(b);
  }
}

void MujocoMap::CheckSizes(const char* where, const Eigen::Ref<const Eigen::VectorXd>& q) const {
  CheckSize(where, "q", q.size(), nq_, "nq");
}

Eigen::Matrix3d MujocoMap::R_BJ(int b, const Eigen::Ref<const Eigen::VectorXd>& q) const {
  return QuaternionAt(q.data() + q_start_[b]).toRotationMatrix().transpose();
}

void MujocoMap::IdtoToMujocoPositions(const Eigen::Ref<const Eigen::VectorXd>& q,
                                      double* mj_qpos) const {
  CheckSizes("MujocoMap::IdtoToMujocoPositions", q);
  for (const BodyIndex b : joints_) {
    const double* qj = q.data() + q_start_[b];
    double* out = mj_qpos + mj_q_start_[b];
    switch (kind_[b]) {
      case Kind::kScalar:
        out[0] = qj[0];
        break;
      case Kind::kPlanar:
        for (int k = 0; k < 3; ++k) out[k] = qj[k];
        break;
      case Kind::kFree: {
        const Eigen::Vector3d p_WB = X_WJ_[b] * Eigen::Vector3d(qj[4], qj[5], qj[6]);
        const Eigen::Quaterniond Q_WJ(X_WJ_[b].linear());
        const Eigen::Quaterniond Q_WB = Q_WJ * Eigen::Quaterniond(qj[0], qj[1], qj[2], qj[3]);
        out[0] = p_WB.x();
        out[1] = p_WB.y();
        out[2] = p_WB.z();
        out[3] = Q_WB.w();
        out[4] = Q_WB.x();
        out[5] = Q_WB.y();
        out[6] = Q_WB.z();
        break;
      }
      case Kind::kNestedFloating:
        for (int k = 0; k < 3; ++k) out[k] = qj[4 + k];
        for (int k = 0; k < 4; ++k) out[3 + k] = qj[k];
        break;
      case Kind::kNone:
        break;
    }
  }
}

void MujocoMap::MujocoToIdtoPositions(const double* mj_qpos, Eigen::VectorXd* q) const {
  q->resize(nq_);
  for (const BodyIndex b : joints_) {
    double* qj = q->data() + q_start_[b];
    const double* in = mj_qpos + mj_q_start_[b];
    switch (kind_[b]) {
      case Kind::kScalar:
        qj[0] = in[0];
        break;
      case Kind::kPlanar:
        for (int k = 0; k < 3; ++k) qj[k] = in[k];
        break;
      case Kind::kFree: {
        const Eigen::Vector3d p_JB = X_WJ_[b].inverse() * Eigen::Vector3d(in[0], in[1], in[2]);
        const Eigen::Quaterniond Q_WJ(X_WJ_[b].linear());
        const Eigen::Quaterniond Q_JB =
            Q_WJ.conjugate() * Eigen::Quaterniond(in[3], in[4], in[5], in[6]);
        qj[0] = Q_JB.w();
        qj[1] = Q_JB.x();
        qj[2] = Q_JB.y();
        qj[3] = Q_JB.z();
        qj[4] = p_JB.x();
        qj[5] = p_JB.y();
        qj[6] = p_JB.z();
        break;
      }
      case Kind::kNestedFloating:
        for (int k = 0; k < 3; ++k) qj[4 + k] = in[k];
        for (int k = 0; k < 4; ++k) qj[k] = in[3 + k];
        break;
      case Kind::kNone:
        break;
    }
  }
}

void MujocoMap::IdtoToMujocoVelocity(const Eigen::Ref<const Eigen::VectorXd>& q,
                                     const Eigen::Ref<const Eigen::VectorXd>& x,
                                     double* x_mj) const {
  CheckSizes("MujocoMap::IdtoToMujocoVelocity", q);
  CheckSize("MujocoMap::IdtoToMujocoVelocity", "x", x.size(), nv_, "nv");
  for (const BodyIndex b : joints_) {
    const double* xj = x.data() + v_start_[b];
    double* out = x_mj + mj_v_start_[b];
    switch (kind_[b]) {
      case Kind::kScalar:
        out[0] = xj[0];
        break;
      case Kind::kPlanar:
        for (int k = 0; k < 3; ++k) out[k] = xj[k];
        break;
      case Kind::kFree:
      case Kind::kNestedFloating: {
        const Eigen::Vector3d w_J(xj[0], xj[1], xj[2]);
        Eigen::Vector3d v_J(xj[3], xj[4], xj[5]);
        if (kind_[b] == Kind::kFree) v_J = X_WJ_[b].linear() * v_J;
        const Eigen::Vector3d w_B = R_BJ(b, q) * w_J;
        for (int k = 0; k < 3; ++k) {
          out[k] = v_J(k);
          out[3 + k] = w_B(k);
        }
        break;
      }
      case Kind::kNone:
        break;
    }
  }
}

void MujocoMap::MujocoToIdtoVelocity(const Eigen::Ref<const Eigen::VectorXd>& q, const double* x_mj,
                                     Eigen::VectorXd* x) const {
  CheckSizes("MujocoMap::MujocoToIdtoVelocity", q);
  x->resize(nv_);
  for (const BodyIndex b : joints_) {
    double* xj = x->data() + v_start_[b];
    const double* in = x_mj + mj_v_start_[b];
    switch (kind_[b]) {
      case Kind::kScalar:
        xj[0] = in[0];
        break;
      case Kind::kPlanar:
        for (int k = 0; k < 3; ++k) xj[k] = in[k];
        break;
      case Kind::kFree:
      case Kind::kNestedFloating: {
        Eigen::Vector3d v_J(in[0], in[1], in[2]);
        if (kind_[b] == Kind::kFree) v_J = X_WJ_[b].linear().transpose() * v_J;
        const Eigen::Vector3d w_J = R_BJ(b, q).transpose() * Eigen::Vector3d(in[3], in[4], in[5]);
        for (int k = 0; k < 3; ++k) {
          xj[k] = w_J(k);
          xj[3 + k] = v_J(k);
        }
        break;
      }
      case Kind::kNone:
        break;
    }
  }
}

void MujocoMap::MujocoToIdtoForce(const Eigen::Ref<const Eigen::VectorXd>& q, const double* tau_mj,
                                  Eigen::VectorXd* tau) const {
  MujocoToIdtoVelocity(q, tau_mj, tau);  // T^T; T is orthogonal.
}

void MujocoMap::IdtoToMujocoForce(const Eigen::Ref<const Eigen::VectorXd>& q,
                                  const Eigen::Ref<const Eigen::VectorXd>& tau,
                                  double* tau_mj) const {
  IdtoToMujocoVelocity(q, tau, tau_mj);  // T = (T^T)^-1 for orthogonal T.
}

void MujocoMap::IdtoToMujocoState(const Eigen::Ref<const Eigen::VectorXd>& q,
                                  const Eigen::Ref<const Eigen::VectorXd>& v, double* mj_qpos,
                                  double* mj_qvel) const {
  IdtoToMujocoPositions(q, mj_qpos);
  IdtoToMujocoVelocity(q, v, mj_qvel);
}

void MujocoMap::MujocoToIdtoState(const double* mj_qpos, const double* mj_qvel, Eigen::VectorXd* q,
                                  Eigen::VectorXd* v) const {
  MujocoToIdtoPositions(mj_qpos, q);
  MujocoToIdtoVelocity(*q, mj_qvel, v);
}

void MujocoMap::VelocityMap(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::MatrixXd* T) const {
  CheckSizes("MujocoMap::VelocityMap", q);
  T->setZero(nv_, nv_);
  for (const BodyIndex b : joints_) {
    const int iv = v_start_[b];
    const int mv = mj_v_start_[b];
    switch (kind_[b]) {
      case Kind::kScalar:
        (*T)(mv, iv) = 1.0;
        break;
      case Kind::kPlanar:
        T->block<3, 3>(mv, iv).setIdentity();
        break;
      case Kind::kFree:
      case Kind::kNestedFloating:
        if (kind_[b] == Kind::kFree) {
          T->block<3, 3>(mv, iv + 3) = X_WJ_[b].linear();
        } else {
          T->block<3, 3>(mv, iv + 3).setIdentity();
        }
        T->block<3, 3>(mv + 3, iv) = R_BJ(b, q);
        break;
      case Kind::kNone:
        break;
    }
  }
}

void IdtoToMujocoState(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                       const Eigen::Ref<const Eigen::VectorXd>& v, double* mj_qpos,
                       double* mj_qvel) {
  MujocoMap(model).IdtoToMujocoState(q, v, mj_qpos, mj_qvel);
}

void MujocoToIdtoState(const Model& model, const double* mj_qpos, const double* mj_qvel,
                       Eigen::VectorXd* q, Eigen::VectorXd* v) {
  MujocoMap(model).MujocoToIdtoState(mj_qpos, mj_qvel, q, v);
}

void IdtoToMujocoVelocityMap(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                             Eigen::MatrixXd* T) {
  MujocoMap(model).VelocityMap(q, T);
}

}  // namespace idto
