#pragma once

// A small scene for the viewer's tests: a ground half-space, a free ball that falls onto it and
// slides, a two-link arm (capsule, box and cylinder) far from both, and a welded table; and a
// many-body scene for the frame-rate check.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/idto.hpp"
#include "idto/viz/html_animation.hpp"

namespace idto::test {

inline BodyInertia VizInertia(double m) {
  BodyInertia I;
  I.mass = m;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01 * m;
  return I;
}

/// Ground, "ball" (floating, sphere r = 0.1), "upper" / "forearm" (revolute about y at
/// (0, 1, 1): a capsule, then a box and a cylinder), "table" (welded to the world, a box).
inline Model VizScene() {
  ModelBuilder b("viz_scene");
  b.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  JointSpec free;
  free.name = "ball_free";
  free.type = JointType::kFloating;
  const BodyIndex ball = b.AddBody("ball", VizInertia(1.0), kWorldBody, free);
  b.AddGeometry("ball_sphere", ball, Eigen::Isometry3d::Identity(), Sphere{0.1});
  JointSpec shoulder;
  shoulder.name = "shoulder";
  shoulder.axis = Eigen::Vector3d::UnitY();
  shoulder.X_PJ.translation() << 0.0, 1.0, 1.0;
  const BodyIndex upper = b.AddBody("upper", VizInertia(0.5), kWorldBody, shoulder);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  X.translation() << 0.2, 0.0, 0.0;
  b.AddGeometry("upper_capsule", upper, X, Capsule{0.04, 0.3});
  JointSpec elbow = shoulder;
  elbow.name = "elbow";
  elbow.X_PJ = Eigen::Isometry3d::Identity();
  elbow.X_PJ.translation() << 0.4, 0.0, 0.0;
  const BodyIndex forearm = b.AddBody("forearm", VizInertia(0.3), upper, elbow);
  X.translation() << 0.15, 0.0, 0.0;
  b.AddGeometry("forearm_box", forearm, X, Box{Eigen::Vector3d(0.06, 0.06, 0.2)});
  X.translation() << 0.3, 0.0, 0.0;
  b.AddGeometry("forearm_cylinder", forearm, X, Cylinder{0.05, 0.08});
  JointSpec weld;
  weld.name = "table_weld";
  weld.type = JointType::kFixed;
  weld.X_PJ.translation() << -1.0, -0.5, 0.2;
  const BodyIndex table = b.AddBody("table", BodyInertia{}, kWorldBody, weld);
  b.AddGeometry("table_top", table, Eigen::Isometry3d::Identity(),
                Box{Eigen::Vector3d(0.5, 0.4, 0.4)});
  return b.Build();
}

/// 2 s at `rate` Hz: the ball starts at z = 1 (no contact), lands at t = 1 with 5 mm of
/// penetration and slides along +x at 0.5 m/s; the arm turns (shoulder 0 -> 0.8 rad, elbow
/// 0 -> -0.6 rad). With `ghost`, the ghost is the same configuration with the ball 0.3 m
/// further along y.
inline std::vector<AnimationFrame> VizFrames(const Model& model, double rate, bool ghost) {
  const int n = static_cast<int>(std::lround(2.0 * rate));
  std::vector<AnimationFrame> frames(n + 1);
  const int ball_q = model.GetPositionStart("ball_free");
  const int ball_v = model.GetVelocityStart("ball_free");
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate;
    AnimationFrame& f = frames[k];
    f.t = t;
    f.q = model.NeutralConfiguration();
    f.v = Eigen::VectorXd::Zero(model.nv());
    const double s = std::min(t, 1.0);
    const double z = t < 1.0 ? 1.0 - 0.905 * s * s : 0.095;
    const double x = t < 1.0 ? 0.0 : 0.5 * (t - 1.0);
    f.q.segment<3>(ball_q + 4) << x, 0.0, z;
    f.v.segment<3>(ball_v + 3) << (t < 1.0 ? 0.0 : 0.5), 0.0, (t < 1.0 ? -1.81 * s : 0.0);
    f.q(model.GetPositionStart("shoulder")) = 0.4 * t;
    f.q(model.GetPositionStart("elbow")) = -0.3 * t;
    if (ghost) {
      f.q_ghost = f.q;
      f.q_ghost(ball_q + 5) += 0.3;
    }
  }
  return frames;
}

/// `num_bodies` free boxes in a ring, each spinning and bobbing above the ground: a 10 s run at
/// 1 kHz has 10001 frames.
inline Model ManyBodies(int num_bodies) {
  ModelBuilder b("many_bodies");
  b.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  for (int i = 0; i < num_bodies; ++i) {
    JointSpec free;
    free.name = "free" + std::to_string(i);
    free.type = JointType::kFloating;
    const BodyIndex body = b.AddBody("body" + std::to_string(i), VizInertia(1.0), kWorldBody, free);
    b.AddGeometry("box" + std::to_string(i), body, Eigen::Isometry3d::Identity(),
                  Box{Eigen::Vector3d(0.1, 0.08, 0.06)});
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << 0.0, 0.0, 0.08;
    b.AddGeometry("cap" + std::to_string(i), body, X, Capsule{0.02, 0.06});
  }
  return b.Build();
}

inline std::vector<AnimationFrame> ManyBodyFrames(const Model& model, double duration,
                                                  double rate) {
  const int n = static_cast<int>(std::lround(duration * rate));
  const int num = model.num_bodies() - 1;
  std::vector<AnimationFrame> frames(n + 1);
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate;
    frames[k].t = t;
    frames[k].q = model.NeutralConfiguration();
    for (int i = 0; i < num; ++i) {
      const int iq = 7 * i;
      const double angle = 2.0 * M_PI * i / num;
      const Eigen::Quaterniond Q(Eigen::AngleAxisd(t + i, Eigen::Vector3d(1, 1, 1).normalized()));
      frames[k].q.segment<4>(iq) << Q.w(), Q.x(), Q.y(), Q.z();
      frames[k].q.segment<3>(iq + 4) << std::cos(angle), std::sin(angle),
          0.1 + 0.3 * (1.0 + std::sin(3.0 * t + i));
    }
  }
  return frames;
}

}  // namespace idto::test
