// Signed distances: documented degenerate and extreme cases, allocation, and errors (the
// pairs' accuracy is in signed_distance_test.cpp).
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "geometry/signed_distance_reference.hpp"
#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "support/allocation_counter.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using namespace sd_test;  // NOLINT(build/namespaces): the shared references

// ---------------------------------------------------------------------------------------------
// Documented degenerate and extreme cases.

TEST(SignedDistance, ConcentricSpheresUseWorldZ) {
  const Isometry3d X = Translation(0.3, -0.2, 1.0);
  const SignedDistanceResult r = SignedDistance(Sphere{0.5}, X, Sphere{0.2}, X);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.7);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 0.0);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.3, -0.2, 1.5), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.3, -0.2, 0.8), 1e-15);
}

TEST(SignedDistance, ExactTouchingGivesZero) {
  const Isometry3d I = Isometry3d::Identity();
  EXPECT_EQ(SignedDistance(Sphere{0.5}, I, Sphere{0.25}, Translation(0.75, 0, 0)).distance, 0.0);
  EXPECT_EQ(SignedDistance(Sphere{0.5}, Translation(0, 0, 0.5), HalfSpace{}, I).distance, 0.0);
  EXPECT_EQ(SignedDistance(Box{Vector3d(1, 1, 1)}, I, Sphere{0.5}, Translation(1, 0, 0)).distance,
            0.0);
  EXPECT_EQ(SignedDistance(Box{Vector3d(1, 2, 3)}, Translation(0, 0, 1.5), HalfSpace{}, I).distance,
            0.0);
  EXPECT_EQ(SignedDistance(Cylinder{0.5, 2}, Translation(0, 0, 1), HalfSpace{}, I).distance, 0.0);
  EXPECT_EQ(SignedDistance(Capsule{0.5, 1}, I, Capsule{0.5, 1}, Translation(1, 0, 0)).distance,
            0.0);
  // FCL at exact contact: finite, with a normal, distance ~0.
  const SignedDistanceResult r =
      SignedDistance(Box{Vector3d(1, 1, 1)}, I, Box{Vector3d(1, 1, 1)}, Translation(1, 0.2, 0.1));
  ASSERT_TRUE(AllFinite(r));
  EXPECT_NEAR(r.distance, 0.0, 1e-9);
  EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
}

TEST(SignedDistance, SphereCentreOnBoxFaceEdgeAndCorner) {
  const Box box{Vector3d(2.0, 1.0, 0.5)};
  const Isometry3d I = Isometry3d::Identity();
  const Sphere sphere{0.1};
  struct Case {
    Vector3d centre;
    Vector3d normal_from_box;  // documented tie-break: lower axis first, + before −
  };
  const std::vector<Case> cases = {
      {Vector3d(1.0, 0.1, 0.0), Vector3d::UnitX()},      // +x face
      {Vector3d(0.2, -0.5, 0.1), -Vector3d::UnitY()},    // −y face
      {Vector3d(1.0, 0.5, 0.0), Vector3d::UnitX()},      // edge: x wins
      {Vector3d(0.0, -0.5, -0.25), -Vector3d::UnitY()},  // edge: y wins over z
      {Vector3d(-1.0, -0.5, 0.25), -Vector3d::UnitX()},  // corner
      {Vector3d(0.0, 0.0, 0.0), Vector3d::UnitZ()},      // centre: nearest face is ±z, + wins
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.centre.transpose());
    const SignedDistanceResult r =
        SignedDistance(box, I, sphere, Translation(c.centre.x(), c.centre.y(), c.centre.z()));
    ASSERT_TRUE(AllFinite(r));
    EXPECT_NEAR(r.distance, PointSdf(box, I, c.centre) - 0.1, 1e-15);
    EXPECT_EIGEN_NEAR(r.normal_W, c.normal_from_box, 0.0);
    ExpectConsistent(box, I, sphere, Translation(c.centre.x(), c.centre.y(), c.centre.z()), r,
                     1e-15);
  }
}

TEST(SignedDistance, SphereCentreOnCylinderAxisAndCapsuleSegment) {
  const Isometry3d I = Isometry3d::Identity();
  // Cylinder: centre on the axis, the side nearest -> as if displaced along +x.
  SignedDistanceResult r = SignedDistance(Sphere{0.1}, Translation(0, 0, 0.2), Cylinder{0.3, 2}, I);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.4);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitX(), 0.0);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.3, 0, 0.2), 1e-15);
  // Cylinder: centre on the axis, the +z cap nearest.
  r = SignedDistance(Sphere{0.1}, Translation(0, 0, 0.9), Cylinder{0.3, 2}, I);
  EXPECT_NEAR(r.distance, -0.2, 1e-15);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitZ(), 0.0);
  // Capsule: centre on the segment.
  r = SignedDistance(Sphere{0.1}, Translation(0, 0, 0.3), Capsule{0.2, 1}, I);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.3);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitX(), 0.0);
  ExpectConsistent(Sphere{0.1}, Translation(0, 0, 0.3), Capsule{0.2, 1}, I, r, 1e-15);
}

TEST(SignedDistance, CapsuleCapsuleDegenerateConfigurations) {
  const Capsule capsule{0.1, 1.0};
  const Isometry3d I = Isometry3d::Identity();
  // Parallel, overlapping over z in [0.2, 0.5]: witnesses at the middle of the overlap.
  SignedDistanceResult r = SignedDistance(capsule, I, capsule, Translation(0.5, 0.0, 0.7));
  EXPECT_NEAR(r.distance, 0.3, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.1, 0, 0.35), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.4, 0, 0.35), 1e-15);
  // Anti-parallel (B flipped) gives the same.
  Isometry3d X_flip = Translation(0.5, 0.0, 0.7);
  X_flip.linear() = Eigen::AngleAxisd(M_PI, Vector3d::UnitX()).toRotationMatrix();
  r = SignedDistance(capsule, I, capsule, X_flip);
  EXPECT_NEAR(r.distance, 0.3, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.1, 0, 0.35), 1e-15);
  // Parallel without overlap: nearest ends.
  r = SignedDistance(capsule, I, capsule, Translation(0.0, 0.3, 1.4));
  EXPECT_NEAR(r.distance, std::hypot(0.3, 0.4) - 0.2, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0, 0.6 * 0.1, 0.5 + 0.8 * 0.1), 1e-15);
  // Crossing segments: normal along axis_A × axis_B = z × x = +y.
  Isometry3d X_cross = Translation(0.0, 0.0, 0.1);
  X_cross.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
  r = SignedDistance(capsule, I, capsule, X_cross);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.2);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitY(), 1e-15);
  const SignedDistanceResult swapped = SignedDistance(capsule, X_cross, capsule, I);
  EXPECT_EIGEN_NEAR(swapped.normal_W, -Vector3d::UnitY(), 1e-15);
  // Collinear and overlapping: +x of A.
  r = SignedDistance(capsule, I, capsule, Translation(0.0, 0.0, 0.4));
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.2);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitX(), 0.0);
  // Zero-length capsules are spheres.
  r = SignedDistance(Capsule{0.2, 0.0}, I, Capsule{0.3, 0.0}, Translation(0, 1, 0));
  EXPECT_NEAR(r.distance, 0.5, 1e-15);
}

TEST(SignedDistance, ShapesParallelToAHalfSpaceUseTheCentroidOfTheDeepestFeature) {
  const Isometry3d I = Isometry3d::Identity();
  // Box resting on a face, rotated about z: witness at the centre of the bottom face.
  Isometry3d X_box = Translation(0.4, -0.3, 0.45);
  X_box.linear() = Eigen::AngleAxisd(0.7, Vector3d::UnitZ()).toRotationMatrix();
  SignedDistanceResult r = SignedDistance(Box{Vector3d(1, 2, 1)}, X_box, HalfSpace{}, I);
  EXPECT_NEAR(r.distance, -0.05, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.4, -0.3, -0.05), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.4, -0.3, 0.0), 1e-15);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitZ(), 0.0);
  // Box on an edge (rotated 45° about x): witness at the middle of the bottom edge.
  X_box.linear() = Eigen::AngleAxisd(M_PI / 4, Vector3d::UnitX()).toRotationMatrix();
  X_box.translation() = Vector3d(0, 0, 1.0);
  r = SignedDistance(Box{Vector3d(1, 1, 1)}, X_box, HalfSpace{}, I);
  EXPECT_NEAR(r.distance, 1.0 - std::sqrt(0.5), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0, 0, 1.0 - std::sqrt(0.5)), 1e-15);
  // Upright cylinder: centre of the lower cap. Lying cylinder: middle of the lowest line.
  r = SignedDistance(Cylinder{0.3, 1.0}, Translation(1, 2, 0.4), HalfSpace{}, I);
  EXPECT_NEAR(r.distance, -0.1, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(1, 2, -0.1), 1e-15);
  Isometry3d X_lying = Translation(1, 2, 0.25);
  X_lying.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()).toRotationMatrix();
  r = SignedDistance(Cylinder{0.3, 1.0}, X_lying, HalfSpace{}, I);
  EXPECT_NEAR(r.distance, -0.05, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(1, 2, -0.05), 1e-15);
  // Lying capsule: middle of the segment.
  r = SignedDistance(HalfSpace{}, I, Capsule{0.1, 1.0}, X_lying);
  EXPECT_NEAR(r.distance, 0.15, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(1, 2, 0.15), 1e-15);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 0.0);
}

TEST(SignedDistance, HalfSpaceWitnessUnderSymmetricTilts) {
  // Round-off tilts (below the 1e-12 tie tolerance) keep the witness at the face centroid;
  // real tilts move it to the lower edge, on either side: the documented jump.
  const Box box{Vector3d(1, 1, 1)};
  const Isometry3d I = Isometry3d::Identity();
  for (const double tilt : {1e-15, -1e-15, 1e-9, -1e-9}) {
    Isometry3d X = Translation(0, 0, 0.6);
    X.linear() = Eigen::AngleAxisd(tilt, Vector3d::UnitX()).toRotationMatrix();
    const SignedDistanceResult r = SignedDistance(box, X, HalfSpace{}, I);
    EXPECT_NEAR(r.distance, Reference(box, X, HalfSpace{}, I), 1e-15);
    if (std::abs(tilt) < 1e-12) {
      EXPECT_EIGEN_NEAR(r.p_WA.head<2>(), Eigen::Vector2d::Zero(), 1e-15);
    } else {
      EXPECT_NEAR(std::abs(r.p_WA.y()), 0.5, 1e-9);
      EXPECT_NEAR(r.p_WA.x(), 0.0, 1e-15);
    }
  }
}

TEST(SignedDistance, NearlyParallelCapsules) {
  const Capsule capsule{0.1, 1.0};
  const Isometry3d I = Isometry3d::Identity();
  for (const double angle : {1e-3, 1e-5, 1e-7, 3e-8, 1e-8, 1e-10, 1e-14, 1e-17, 0.0}) {
    SCOPED_TRACE(angle);
    // Offset so that the segments do not cross: exact at every angle.
    Isometry3d X = Translation(0.5, 0.0, 0.3);
    X.linear() = Eigen::AngleAxisd(angle, Vector3d::UnitY()).toRotationMatrix();
    SignedDistanceResult r = SignedDistance(capsule, I, capsule, X);
    ASSERT_TRUE(AllFinite(r));
    EXPECT_NEAR(r.distance, Reference(capsule, I, capsule, X), kExactTol);
    ExpectConsistent(capsule, I, capsule, X, r, kExactTol);
    // Witness: middle of the overlap z in [-0.2, 0.5] while parallel up to round-off.
    if (angle < 1e-12) {
      EXPECT_NEAR(r.p_WA.z(), 0.15, 1e-12);
    }
    // Crossing at the middle: documented error bound 1e-16 × size / angle, capped at 1e-8.
    X.translation() = Vector3d(0.0, 0.05, 0.0);
    r = SignedDistance(capsule, I, capsule, X);
    ASSERT_TRUE(AllFinite(r));
    EXPECT_NEAR(r.distance, Reference(capsule, I, capsule, X),
                angle > 0 ? std::min(1e-8, std::max(kExactTol, 1e-16 / angle)) : kExactTol);
  }
}

TEST(SignedDistance, FclPairsNearContactStayFinite) {
  const Isometry3d I = Isometry3d::Identity();
  const Box box{Vector3d(1, 1, 1)};
  const Capsule capsule{0.1, 0.5};
  for (const double gap : {1e-3, 1e-9, 1e-13, 0.0, -1e-13, -1e-9, -1e-3}) {
    SCOPED_TRACE(gap);
    // Capsule lying on the box's top face, and standing on it.
    Isometry3d X_lying = Translation(0.1, 0.0, 0.6 + gap);
    X_lying.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()).toRotationMatrix();
    for (const Isometry3d& X : {X_lying, Translation(0.1, 0.2, 0.85 + gap)}) {
      const SignedDistanceResult r = SignedDistance(box, I, capsule, X);
      ASSERT_TRUE(AllFinite(r));
      EXPECT_NEAR(r.distance, gap, 2e-6);
      EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
      if (std::abs(gap) >= 1e-3) {
        EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 1e-5);
      }
    }
  }
}

TEST(SignedDistance, TinyAndHugeShapesKeepRelativeAccuracy) {
  for (const double scale : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
    SCOPED_TRACE(scale);
    test::Random rng(808);
    for (int k = 0; k < 50; ++k) {
      for (const auto& pairs : {kAnalyticPairs, kFclPairs}) {
        for (const PairCase& pair : pairs) {
          Shape A = RandomShape(&rng, pair.a);
          Shape B = RandomShape(&rng, pair.b);
          auto scale_shape = [scale](Shape* s) {
            std::visit(
                [scale](auto& shape) {
                  using T = std::decay_t<decltype(shape)>;
                  if constexpr (std::is_same_v<T, Sphere>) {
                    shape.radius *= scale;
                  } else if constexpr (std::is_same_v<T, Capsule> || std::is_same_v<T, Cylinder>) {
                    shape.radius *= scale;
                    shape.length *= scale;
                  } else if constexpr (std::is_same_v<T, Box>) {
                    shape.size *= scale;
                  }
                },
                *s);
          };
          scale_shape(&A);
          scale_shape(&B);
          Isometry3d X_WA = RandomPose(&rng, 0.6);
          Isometry3d X_WB = RandomPose(&rng, 0.6);
          X_WA.translation() *= scale;
          X_WB.translation() *= scale;
          const SignedDistanceResult r = SignedDistance(A, X_WA, B, X_WB);
          ASSERT_TRUE(AllFinite(r)) << pair.name;
          EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
          if (r.exact) {
            EXPECT_NEAR(r.distance, Reference(A, X_WA, B, X_WB), kExactTol * scale) << pair.name;
          } else {
            // Scale invariance of the FCL path: the same answer as at unit scale, scaled.
            EXPECT_NEAR(PointSdf(A, X_WA, r.p_WA), 0.0, 1e-5 * scale) << pair.name;
            EXPECT_NEAR(PointSdf(B, X_WB, r.p_WB), 0.0, 1e-5 * scale) << pair.name;
          }
        }
      }
    }
  }
}

TEST(SignedDistance, AnalyticPairsAllocateNothing) {
  if (!test::AllocationCountingAvailable()) GTEST_SKIP() << "malloc counting unavailable";
  for (const PairCase& pair : kAnalyticPairs) {
    test::Random rng(1001 + pair.a * 7 + pair.b);
    std::vector<Shape> A, B;
    std::vector<Isometry3d> X_WA, X_WB;
    for (int k = 0; k < 50; ++k) {
      A.push_back(RandomShape(&rng, pair.a));
      B.push_back(RandomShape(&rng, pair.b));
      X_WA.push_back(RandomPose(&rng, 0.6));
      X_WB.push_back(RandomPose(&rng, 0.6));
    }
    double sum = 0;
    test::ScopedAllocationCounter counter;
    for (int k = 0; k < 50; ++k) {
      sum += SignedDistance(A[k], X_WA[k], B[k], X_WB[k]).distance;
      sum += SignedDistance(B[k], X_WB[k], A[k], X_WA[k]).distance;
    }
    EXPECT_EQ(counter.count(), 0) << pair.name;
    EXPECT_TRUE(std::isfinite(sum));
  }
  // The FCL path does allocate (its shapes): this also shows the counter counts.
  const Isometry3d I = Isometry3d::Identity();
  test::ScopedAllocationCounter counter;
  const double phi =
      SignedDistance(Capsule{0.1, 0.2}, I, Box{Vector3d::Ones()}, Translation(2, 0, 0)).distance;
  EXPECT_GT(counter.count(), 0);
  EXPECT_NEAR(phi, 2 - 0.5 - 0.1, 1e-9);
}

TEST(SignedDistance, SignedDistanceIsExactTable) {
  const std::vector<Shape> shapes = {Sphere{1}, Capsule{1, 1}, Cylinder{1, 1},
                                     Box{Vector3d::Ones()}, HalfSpace{}};
  // Rows/columns: sphere, capsule, cylinder, box, half-space.
  const bool expected[5][5] = {{true, true, true, true, true},
                               {true, true, false, false, true},
                               {true, false, false, false, true},
                               {true, false, false, false, true},
                               {true, true, true, true, false}};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      EXPECT_EQ(SignedDistanceIsExact(shapes[i], shapes[j]), expected[i][j])
          << ShapeName(shapes[i]) << "-" << ShapeName(shapes[j]);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Errors.

TEST(SignedDistance, InvalidArgumentsNameTheArgument) {
  const Isometry3d I = Isometry3d::Identity();
  EXPECT_THAT([&] { SignedDistance(HalfSpace{}, I, HalfSpace{}, I); },
              ThrowsMessage<InvalidArgument>(
                  HasSubstr("idto::SignedDistance: (A, B) is (half_space, half_space)")));
  EXPECT_THAT([&] { SignedDistance(Sphere{-1}, I, Sphere{1}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("A.radius is -1; expected a finite "
                                                       "positive length")));
  EXPECT_THAT(
      [&] {
        SignedDistance(Sphere{1}, I, Capsule{0.1, -2}, I);
      },
      ThrowsMessage<InvalidArgument>(HasSubstr("B.length is -2")));
  EXPECT_THAT(
      [&] {
        SignedDistance(Sphere{1}, I, Cylinder{0.1, 0.0}, I);
      },
      ThrowsMessage<InvalidArgument>(HasSubstr("B.length is 0")));
  EXPECT_THAT([&] { SignedDistance(Box{Vector3d(1, 0, 1)}, I, HalfSpace{}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("A.size(1) is 0")));
  EXPECT_THAT(
      [&] { SignedDistance(Sphere{std::numeric_limits<double>::quiet_NaN()}, I, HalfSpace{}, I); },
      ThrowsMessage<InvalidArgument>(HasSubstr("A.radius is nan")));
  Isometry3d bad = I;
  bad.translation().y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT([&] { SignedDistance(Sphere{1}, I, Sphere{1}, bad); },
              ThrowsMessage<InvalidArgument>(HasSubstr("X_WB(1, 3) is nan")));
  bad = I;
  bad.linear()(0, 0) = 2.0;
  EXPECT_THAT([&] { SignedDistance(Sphere{1}, bad, Sphere{1}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("X_WA is not a rigid transform")));
  bad = I;
  bad.linear()(2, 2) = -1.0;  // a reflection
  EXPECT_THAT([&] { SignedDistance(Sphere{1}, bad, Sphere{1}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("det R = -1")));
  EXPECT_THAT(
      [&] { SignedDistanceFcl(Sphere{1}, I, HalfSpace{}, I); },
      ThrowsMessage<InvalidArgument>(HasSubstr("idto::SignedDistanceFcl: B is half_space")));
}

// ---------------------------------------------------------------------------------------------
// Inscribed spheres.

TEST(InscribedSpheres, DefaultIsNineSpheresInsideThePapersCube) {
  const Box cube{Vector3d::Constant(0.15)};
  const std::vector<InscribedSphere> spheres = InscribedSpheres(cube);
  ASSERT_EQ(spheres.size(), 9u);
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_DOUBLE_EQ(spheres[i].sphere.radius, 0.0375);
    EXPECT_EIGEN_NEAR(spheres[i].X_BoxSphere.translation().cwiseAbs(), Vector3d::Constant(0.0375),
                      1e-17);
  }
  EXPECT_EIGEN_NEAR(spheres[0].X_BoxSphere.translation(), Vector3d::Constant(-0.0375), 1e-17);
  EXPECT_EIGEN_NEAR(spheres[1].X_BoxSphere.translation(), Vector3d(0.0375, -0.0375, -0.0375),
                    1e-17);
  EXPECT_DOUBLE_EQ(spheres[8].sphere.radius, 0.075);
  EXPECT_EIGEN_NEAR(spheres[8].X_BoxSphere.translation(), Vector3d::Zero(), 0.0);
}

TEST(InscribedSpheres, SpheresAreInsideAndTouchTheFaces) {
  const Box box{Vector3d(0.4, 0.2, 0.3)};
  for (const int n : {2, 3, 4}) {
    InscribedSpheresOptions options;
    options.num_per_axis = n;
    options.radius_fraction = 0.2;
    const auto spheres = InscribedSpheres(box, options);
    EXPECT_EQ(spheres.size(),
              static_cast<std::size_t>(n * n * n - (n - 2) * (n - 2) * (n - 2) + 1));
    // Each sphere is inside: the box's SDF at its centre is at most −radius.
    for (const auto& s : spheres) {
      EXPECT_LE(PointSdf(box, Isometry3d::Identity(), s.X_BoxSphere.translation()),
                -s.sphere.radius + 1e-15);
    }
    // Resting on any face, the spheres touch the plane exactly where the box does, and never
    // go below it when the box is tilted.
    test::Random rng(909);
    for (int k = 0; k < 50; ++k) {
      const Isometry3d X_WBox = RandomPose(&rng, 0.5);
      const double box_distance =
          SignedDistance(box, X_WBox, HalfSpace{}, Isometry3d::Identity()).distance;
      double spheres_distance = std::numeric_limits<double>::infinity();
      for (const auto& s : spheres) {
        spheres_distance = std::min(
            spheres_distance,
            SignedDistance(s.sphere, X_WBox * s.X_BoxSphere, HalfSpace{}, Isometry3d::Identity())
                .distance);
      }
      EXPECT_GE(spheres_distance, box_distance - 1e-15);
    }
    const double flat =
        SignedDistance(box, Translation(0, 0, 0.1), HalfSpace{}, Isometry3d::Identity()).distance;
    double flat_spheres = std::numeric_limits<double>::infinity();
    for (const auto& s : spheres) {
      flat_spheres =
          std::min(flat_spheres, SignedDistance(s.sphere, Translation(0, 0, 0.1) * s.X_BoxSphere,
                                                HalfSpace{}, Isometry3d::Identity())
                                     .distance);
    }
    EXPECT_NEAR(flat_spheres, flat, 1e-15);
  }
}

TEST(InscribedSpheres, InvalidOptionsThrow) {
  InscribedSpheresOptions options;
  options.num_per_axis = 1;
  EXPECT_THAT([&] { InscribedSpheres(Box{Vector3d::Ones()}, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("options.num_per_axis is 1")));
  options = {};
  options.radius_fraction = 0.6;
  EXPECT_THAT([&] { InscribedSpheres(Box{Vector3d::Ones()}, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("options.radius_fraction is 0.6")));
  EXPECT_THAT(
      [&] { InscribedSpheres(Box{Vector3d(1, -1, 1)}); },
      ThrowsMessage<InvalidArgument>(HasSubstr("idto::InscribedSpheres: box.size(1) is -1")));
}

}  // namespace
}  // namespace idto
