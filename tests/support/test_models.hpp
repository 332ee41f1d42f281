#pragma once

/// @file
/// Models built in code for tests: random trees with every joint type, rotated joint frames,
/// offset centres of mass, full inertias and welded bodies.

#include <cmath>
#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/multibody/model.hpp"
#include "idto/multibody/model_builder.hpp"
#include "support/random.hpp"

namespace idto::test {

/// A random physically valid inertia (principal moments satisfying the triangle inequality,
/// rotated by a random rotation) with a random centre of mass.
inline BodyInertia RandomInertia(Random* rng) {
  BodyInertia I;
  I.mass = rng->Uniform(0.5, 3.0);
  I.p_BBcm = rng->Vector(3, -0.2, 0.2);
  const Eigen::Vector3d moments(rng->Uniform(0.04, 0.075), rng->Uniform(0.04, 0.075),
                                rng->Uniform(0.04, 0.075));
  const Eigen::Matrix3d R = rng->Quaternion().toRotationMatrix();
  I.I_BBcm_B = R * moments.asDiagonal() * R.transpose();
  return I;
}

inline Eigen::Isometry3d RandomPose(Random* rng, double max_offset = 0.4) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rng->Quaternion().toRotationMatrix();
  X.translation() = rng->Vector(3, -max_offset, max_offset);
  return X;
}

/// Options for RandomTreeModel.
struct RandomTreeOptions {
  int num_bodies{8};
  BaseType base{BaseType::kFloating};
  bool include_prismatic{true};
  bool include_welds{true};
  bool include_planar{true};    ///< a planar joint deeper in the tree
  bool include_floating{true};  ///< a floating joint deeper in the tree (not at the root)
  bool with_damping{true};
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  /// Attach a random shape (sphere, capsule, cylinder or box, cycling) at a random pose to every
  /// body, and a tilted half-space and a sphere to the world (contact tests).
  bool with_geometry{false};
};

/// A random tree: the root on the requested base, then bodies attached to random earlier
/// bodies by revolute, continuous, prismatic, fixed, planar and floating joints.
inline Model RandomTreeModel(std::uint32_t seed, const RandomTreeOptions& options = {}) {
  Random rng(seed);
  ModelBuilder builder("random_tree_" + std::to_string(seed));
  builder.SetGravity(options.gravity);
  JointSpec root;
  root.name = "root_joint";
  root.X_PJ = RandomPose(&rng, 0.5);
  switch (options.base) {
    case BaseType::kFixed:
      root.type = JointType::kRevolute;
      break;
    case BaseType::kFloating:
      root.type = JointType::kFloating;
      break;
    case BaseType::kPlanar:
      root.type = JointType::kPlanar;
      break;
  }
  root.axis = rng.Vector(3).normalized();
  root.damping = options.with_damping ? 0.3 : 0.0;
  builder.AddBody("body1", RandomInertia(&rng), kWorldBody, root);
  bool placed_planar = !options.include_planar, placed_floating = !options.include_floating;
  for (int i = 2; i <= options.num_bodies; ++i) {
    JointSpec j;
    j.name = "joint" + std::to_string(i);
    j.X_PJ = RandomPose(&rng);
    j.axis = rng.Vector(3) * 2.0;  // deliberately not unit: the builder normalizes
    j.damping = options.with_damping ? rng.Uniform(0.0, 0.5) : 0.0;
    const int kind = i % 5;
    if (kind == 0 && options.include_prismatic) {
      j.type = JointType::kPrismatic;
    } else if (kind == 1 && options.include_welds) {
      j.type = JointType::kFixed;
    } else if (kind == 2) {
      j.type = JointType::kContinuous;
    } else {
      j.type = JointType::kRevolute;
    }
    if (!placed_planar && i == 4) {
      j.type = JointType::kPlanar;
      placed_planar = true;
    }
    if (!placed_floating && i == 7) {
      j.type = JointType::kFloating;
      placed_floating = true;
    }
    // A fixed joint has no damping (ModelBuilder refuses it); the draw above keeps the sequence.
    if (j.type == JointType::kFixed) j.damping = 0.0;
    const BodyIndex parent = static_cast<BodyIndex>(rng.engine()() % (i - 1)) + 1;
    builder.AddBody("body" + std::to_string(i), RandomInertia(&rng), parent, j);
  }
  if (options.with_geometry) {
    for (int i = 1; i <= options.num_bodies; ++i) {
      const double r = rng.Uniform(0.05, 0.2), l = rng.Uniform(0.05, 0.3);
      Shape shape;
      switch (i % 4) {
        case 0:
          shape = Sphere{r};
          break;
        case 1:
          shape = Capsule{r, l};
          break;
        case 2:
          shape = Sphere{r};  // spheres carry most contacts (cylinders and boxes vs half-space)
          break;
        default:
          shape = Capsule{0.5 * r, l};
      }
      builder.AddGeometry("geometry" + std::to_string(i), static_cast<BodyIndex>(i),
                          RandomPose(&rng, 0.2), shape);
    }
    Eigen::Isometry3d X_WH = Eigen::Isometry3d::Identity();
    X_WH.linear() =
        Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 0.5, 0.0).normalized()).toRotationMatrix();
    X_WH.translation() = Eigen::Vector3d(0.0, 0.0, -0.3);
    builder.AddGeometry("ground", kWorldBody, X_WH, HalfSpace{});
    builder.AddGeometry("post", kWorldBody, RandomPose(&rng, 0.3), Sphere{0.25});
  }
  return builder.Build();
}

/// A random configuration: joint coordinates in [-1, 1], random unit quaternions.
inline Eigen::VectorXd RandomConfiguration(const Model& model, Random* rng) {
  Eigen::VectorXd q = rng->Vector(model.nq());
  for (JointIndex j : model.floating_joints()) {
    const Eigen::Quaterniond Q = rng->Quaternion();
    const int i = model.position_start(j);
    q(i) = Q.w();
    q(i + 1) = Q.x();
    q(i + 2) = Q.y();
    q(i + 3) = Q.z();
  }
  return q;
}

/// A body of mass m (kg) with its centre of mass at com and a small isotropic inertia.
inline BodyInertia PointLikeMass(double m, const Eigen::Vector3d& com) {
  BodyInertia I;
  I.mass = m;
  I.p_BBcm = com;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 1e-3 * m;
  return I;
}

/// A solid ball of mass m (kg) and radius r (m), centred at the body origin.
inline BodyInertia SolidBall(double m, double r) {
  BodyInertia I;
  I.mass = m;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.4 * m * r * r;
  return I;
}

/// A ground plane, 60 random static spheres (every third welded to a fixed "table" body, the
/// rest on the world; placement from `seed`) and two free balls "ball1", "ball2" whose sphere
/// sits 5 cm off the body origin. With `with_arm`, also a hinged "arm" with a "tip" sphere.
/// For the broad phase over static geometry.
inline Model StaticCrowd(std::uint32_t seed, bool with_arm) {
  ModelBuilder builder("crowd");
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  JointSpec weld;
  weld.name = "table_weld";
  weld.type = JointType::kFixed;
  weld.X_PJ.translation() << 0.3, -0.2, 0.0;
  const BodyIndex table = builder.AddBody("table", BodyInertia{}, kWorldBody, weld);
  Random rng(seed);
  for (int i = 0; i < 60; ++i) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = rng.Vector(3, -1.0, 1.0);
    X.translation().z() = std::abs(X.translation().z());
    builder.AddGeometry("static" + std::to_string(i), i % 3 == 0 ? table : kWorldBody, X,
                        Sphere{rng.Uniform(0.02, 0.1)});
  }
  for (const char* name : {"ball1", "ball2"}) {
    JointSpec j;
    j.name = std::string(name) + "_free";
    j.type = JointType::kFloating;
    const BodyIndex b = builder.AddBody(name, SolidBall(0.5, 0.1), kWorldBody, j);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << 0.05, 0.0, 0.0;  // off-centre: the bound is not at the body origin
    builder.AddGeometry(std::string(name) + "_sphere", b, X, Sphere{0.1});
  }
  if (with_arm) {
    JointSpec shoulder;
    shoulder.name = "shoulder";
    shoulder.type = JointType::kRevolute;
    shoulder.axis = Eigen::Vector3d::UnitY();
    shoulder.X_PJ.translation() << 0.0, 0.0, 0.6;
    const BodyIndex arm = builder.AddBody("arm", SolidBall(1.0, 0.1), kWorldBody, shoulder);
    Eigen::Isometry3d X_tip = Eigen::Isometry3d::Identity();
    X_tip.translation() << 0.5, 0.0, 0.0;
    builder.AddGeometry("tip", arm, X_tip, Sphere{0.03});
  }
  return builder.Build();
}

/// A free 1 kg body "ball" on a floating joint "free" (inertia 0.01 I), without gravity or
/// contact geometry.
inline Model FreeBodyWithoutGravity() {
  ModelBuilder b;
  BodyInertia I;
  I.mass = 1.0;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01;
  JointSpec free;
  free.name = "free";
  free.type = JointType::kFloating;
  b.AddBody("ball", I, kWorldBody, free);
  b.SetGravity(Eigen::Vector3d::Zero());
  return b.Build();
}

/// 1 kg at 1 m on a hinge about y; q = 0 hangs down, q = pi is upright.
inline Model Pendulum(double damping = 0.1) {
  ModelBuilder b("pendulum");
  JointSpec j;
  j.name = "hinge";
  j.type = JointType::kRevolute;
  j.axis = Eigen::Vector3d::UnitY();
  j.damping = damping;
  b.AddBody("link", PointLikeMass(1.0, Eigen::Vector3d(0, 0, -1)), kWorldBody, j);
  return b.Build();
}

/// A free 0.2 kg ball (radius 5 cm) above a ground half-space and a two-link finger with a
/// fingertip sphere that can touch it: a floating base with contact (nq = 9, nv = 8).
inline Model BallAndFinger() {
  ModelBuilder b("ball_and_finger");
  b.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  JointSpec free;
  free.name = "ball_free";
  free.type = JointType::kFloating;
  BodyInertia ball;
  ball.mass = 0.2;
  ball.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.4 * 0.2 * 0.05 * 0.05;
  const BodyIndex bb = b.AddBody("ball", ball, kWorldBody, free);
  b.AddGeometry("ball_sphere", bb, Eigen::Isometry3d::Identity(), Sphere{0.05});
  JointSpec j1;
  j1.name = "j1";
  j1.type = JointType::kRevolute;
  j1.axis = Eigen::Vector3d::UnitY();
  j1.X_PJ.translation() << -0.3, 0.0, 0.3;
  const BodyIndex l1 =
      b.AddBody("l1", PointLikeMass(0.3, Eigen::Vector3d(0.1, 0, 0)), kWorldBody, j1);
  JointSpec j2 = j1;
  j2.name = "j2";
  j2.X_PJ.translation() << 0.2, 0.0, 0.0;
  const BodyIndex l2 = b.AddBody("l2", PointLikeMass(0.2, Eigen::Vector3d(0.1, 0, 0)), l1, j2);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << 0.2, 0.0, 0.0;
  b.AddGeometry("tip", l2, X, Sphere{0.02});
  return b.Build();
}

}  // namespace idto::test
