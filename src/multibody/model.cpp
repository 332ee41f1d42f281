#include "idto/multibody/model.hpp"

#include <atomic>
#include <cstdint>

#include <algorithm>
#include <string>

#include "idto/core/errors.hpp"

namespace idto {

namespace {

template <typename Map>
int LookUp(const Map& map, const std::string& name, const char* where, const char* kind) {
  const auto it = map.find(name);
  if (it == map.end()) {
    ThrowInvalidArgument(where, kind, "\"" + name + "\"",
                         std::string("the name of a ") + kind + " of the model");
  }
  return it->second;
}

}  // namespace

Model::Model() {
  static std::atomic<std::uint64_t> next_tag{1};
  tag_ = next_tag.fetch_add(1, std::memory_order_relaxed);
  body_name_ = {"world"};
  parent_ = {-1};
  mobilized_ = {0};
  X_MB_ = {RigidTransform::Identity()};
  body_inertia_ = {BodyInertia{}};
  inertia_ = {SpatialInertia::Zero()};
  joint_name_ = {""};
  joint_type_ = {JointType::kFixed};
  q_start_ = {0};
  v_start_ = {0};
  X_PJ_ = {Eigen::Isometry3d::Identity()};
  axis_ = {Eigen::Vector3d::UnitZ()};
  joint_damping_ = {0.0};
  moving_parent_ = {-1};
  X_MJ_ = {RigidTransform::Identity()};
  X_MJ_translation_only_ = {true};
  planar_e1_ = {Eigen::Vector3d::UnitX()};
  planar_e2_ = {Eigen::Vector3d::UnitY()};
  frame_name_ = {"world"};
  frame_body_ = {0};
  X_BF_ = {Eigen::Isometry3d::Identity()};
  body_index_["world"] = 0;
  frame_index_["world"] = 0;
}

BodyIndex Model::GetBodyIndex(const std::string& name) const {
  return LookUp(body_index_, name, "Model::GetBodyIndex", "body");
}

JointIndex Model::GetJointIndex(const std::string& name) const {
  return LookUp(joint_index_, name, "Model::GetJointIndex", "joint");
}

int Model::GetPositionStart(const std::string& joint_name) const {
  return q_start_[LookUp(joint_index_, joint_name, "Model::GetPositionStart", "joint")];
}

int Model::GetVelocityStart(const std::string& joint_name) const {
  return v_start_[LookUp(joint_index_, joint_name, "Model::GetVelocityStart", "joint")];
}

FrameIndex Model::GetFrameIndex(const std::string& name) const {
  return LookUp(frame_index_, name, "Model::GetFrameIndex", "frame");
}

GeometryIndex Model::GetGeometryIndex(const std::string& name) const {
  return LookUp(geometry_index_, name, "Model::GetGeometryIndex", "geometry");
}

const std::string& Model::velocity_name(int i) const {
  if (i < 0 || i >= nv_) {
    ThrowInvalidArgument("Model::velocity_name", "i", std::to_string(i),
                         "an index in [0, " + std::to_string(nv_) + ")");
  }
  return joint_name_[velocity_owner_[i]];
}

const std::string& Model::position_name(int i) const {
  if (i < 0 || i >= nq_) {
    ThrowInvalidArgument("Model::position_name", "i", std::to_string(i),
                         "an index in [0, " + std::to_string(nq_) + ")");
  }
  return joint_name_[position_owner_[i]];
}

double Model::total_mass() const {
  double m = 0.0;
  for (const BodyInertia& b : body_inertia_) m += b.mass;
  return m;
}

Eigen::VectorXd Model::NeutralConfiguration() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq_);
  for (BodyIndex b : moving_bodies_) {
    const int i = q_start_[b];
    switch (joint_type_[b]) {
      case JointType::kFloating:
        q(i) = 1.0;
        break;
      case JointType::kRevolute:
      case JointType::kPrismatic:
        q(i) = std::clamp(0.0, lower_limits_(i), upper_limits_(i));
        break;
      default:
        break;
    }
  }
  return q;
}

void Model::CheckConfiguration(const char* where, const char* argument,
                               const Eigen::Ref<const Eigen::VectorXd>& q) const {
  if (q.size() != nq_) CheckSize(where, argument, q.size(), nq_, "model.nq()");
}

void Model::CheckVelocity(const char* where, const char* argument,
                          const Eigen::Ref<const Eigen::VectorXd>& v) const {
  if (v.size() != nv_) CheckSize(where, argument, v.size(), nv_, "model.nv()");
}

}  // namespace idto
