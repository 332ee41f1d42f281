#pragma once

/// @file
/// Signed distance between two shapes (design.md §5b), analytic wherever the paper needs it.
///
/// Conventions. `SignedDistance(A, X_WA, B, X_WB)` returns the signed distance φ [m] between
/// shape A posed at X_WA and shape B posed at X_WB: positive when they are apart, zero when they
/// touch, negative in penetration (minus the penetration depth: the length of the smallest
/// translation that separates them). `normal_W` is the unit normal pointing from A to B;
/// `p_WA` lies on A's surface and `p_WB` on B's surface (in penetration, each is the point of
/// its shape deepest inside the other), and (p_WB − p_WA)·normal_W = distance. Moving B by a
/// small translation δ changes the distance by normal_W·δ wherever the answer is smooth.
///
/// Pair support. These pairs, in either order, are analytic and exact to machine precision,
/// separated and penetrating (`exact = true`):
///
///   sphere–sphere, sphere–half-space, sphere–capsule, sphere–cylinder, sphere–box,
///   capsule–half-space, capsule–capsule, cylinder–half-space, box–half-space.
///
/// The other pairs of the finite shapes (capsule–cylinder, capsule–box, cylinder–cylinder,
/// cylinder–box, box–box) are answered by FCL's iterative GJK/EPA (`exact = false`), whose
/// errors (about 1e-10 m separated, 1e-6 m in penetration, for shapes of unit size) make
/// finite-difference gradients noisy; docs/contact.md gives the measurements. Half-space vs
/// half-space is an error. A pair of different shape types is always computed in one canonical
/// order, so SignedDistance(B, A) is exactly SignedDistance(A, B) with the normal negated and
/// the witnesses swapped (also on the FCL path).
///
/// Where the normal or the witnesses jump (deterministic choices, all documented here):
/// - sphere–sphere with coincident centres: normal_W = +z of the world.
/// - sphere–capsule with the sphere centre on the capsule's segment, and sphere–cylinder with
///   the centre on the cylinder's axis and the side nearest: as if the centre were displaced
///   along +x of the capsule/cylinder frame (normal_W = −x of that frame when the sphere is A).
/// - capsule–capsule with intersecting segments: normal_W = (axis_A × axis_B)/|axis_A × axis_B|
///   (axis = +z of each frame); with collinear overlapping segments: +x of A's frame.
/// - capsule–capsule with parallel axes (up to round-off: the gap varies by less than 1e-12 of
///   the size along the overlap): witnesses at the midpoint of the overlap of the two segments
///   (or the nearest endpoints when they do not overlap); as soon as the axes tilt, the
///   witnesses jump towards the nearer end of the overlap. Within 3e-8 rad of parallel, segments
///   that cross each other carry a distance error of order 1e-16 × size / angle (≤ 1e-8 of the
///   size); every other configuration is exact.
/// - sphere–cylinder and sphere–box with the sphere centre inside the solid: the nearest face
///   (ties broken in the order side, +z cap, −z cap for the cylinder; x, y, z and + before −
///   for the box); centre exactly on a face, edge or corner: the same tie-break (distance −r).
/// - capsule-, cylinder- and box–half-space with a deepest feature rather than a deepest point
///   (a segment, an edge, a face parallel to the plane, up to a relative tie tolerance of 1e-12
///   of the shape's size): the witness on the shape is the centroid of that deepest feature,
///   so it does not flicker between vertices under round-off. It still jumps from one end to
///   the other when the tilt changes sign. The normal (the half-space's) never jumps.
///
/// Thread safety and cost: all functions are reentrant. Analytic pairs allocate nothing and take
/// 20–60 ns; the FCL path creates its FCL shapes per call (heap) and takes microseconds
/// (docs/contact.md, "Cost per query").

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/geometry/shape.hpp"

namespace idto {

/// The answer of a signed distance query between shapes A and B.
struct SignedDistanceResult {
  double distance{0.0};  ///< signed distance φ [m]; negative in penetration
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};  ///< unit normal from A to B, world frame
  Eigen::Vector3d p_WA{Eigen::Vector3d::Zero()};       ///< witness point on A's surface [m], world
  Eigen::Vector3d p_WB{Eigen::Vector3d::Zero()};       ///< witness point on B's surface [m], world
  bool exact{true};  ///< true for analytic pairs; false when answered by FCL (GJK/EPA)
};

/// Signed distance between shape A at pose X_WA and shape B at pose X_WB (see the file comment
/// for conventions and pair support).
///
/// @param A, B shapes in their own frames (dimensions in m).
/// @param X_WA, X_WB poses of the shape frames in the world; the linear part must be a rotation.
/// @throws InvalidArgument if a shape has a non-positive or non-finite dimension (a capsule's
///   length may be zero), if a pose is non-finite or not a rigid transform, or if both shapes
///   are half-spaces; the message names the argument ("A.radius", "X_WB(0, 3)", ...).
/// @throws std::runtime_error if FCL fails on a non-analytic pair (not observed in tests).
SignedDistanceResult SignedDistance(const Shape& A, const Eigen::Isometry3d& X_WA, const Shape& B,
                                    const Eigen::Isometry3d& X_WB);

/// True when SignedDistance answers the pair (A, B) analytically (`exact = true`), false when
/// it goes through FCL, and false for half-space vs half-space (which has no answer).
bool SignedDistanceIsExact(const Shape& A, const Shape& B);

/// FCL's answer for any pair without a half-space, in the order given (no canonical
/// reordering): a test oracle and a baseline for benchmarks. `exact` is false. Separated poses
/// use FCL's GJK distance (FCL's own solver for curved shapes, libccd for box–box), penetration
/// uses FCL's signed distance (libccd EPA); the problem is scaled to unit size first so that the
/// tolerances are relative. For sphere pairs FCL has closed forms of its own.
/// @throws InvalidArgument for invalid shapes or poses as SignedDistance, and for any pair
///   with a half-space (FCL 0.7 crashes on sphere–half-space distance).
SignedDistanceResult SignedDistanceFcl(const Shape& A, const Eigen::Isometry3d& X_WA,
                                       const Shape& B, const Eigen::Isometry3d& X_WB);

/// One sphere of a box approximated by inscribed spheres.
struct InscribedSphere {
  Sphere sphere;                                                 ///< the sphere (radius in m)
  Eigen::Isometry3d X_BoxSphere{Eigen::Isometry3d::Identity()};  ///< sphere frame in box frame
};

/// How InscribedSpheres places its spheres.
struct InscribedSpheresOptions {
  /// Grid points per axis (>= 2). Spheres sit on the points of an n×n×n grid that lie on the
  /// grid's boundary: n³ − (n−2)³ of them (8 for n = 2, 26 for n = 3).
  int num_per_axis{2};
  /// Radius of the grid spheres as a fraction of the box's smallest side, in (0, 0.5]. The
  /// outermost spheres touch the box faces, so each corner is rounded by r(√3 − 1).
  double radius_fraction{0.25};
  /// Also add the largest sphere centred in the box (radius = smallest side / 2), which carries
  /// contact on the faces between the grid spheres.
  bool center_sphere{true};
};

/// Replaces a box by spheres that lie inside it, as the paper does for the bi-manual box
/// (Remark "collision geometries": sharp corners make the normal jump, so the box is modelled
/// with 9 inscribed spheres; the paper does not give their layout). The defaults give 9
/// spheres: one of radius s/4 in each corner (s = smallest side), touching the three faces of
/// the corner, plus a centre sphere of radius s/2 touching the faces across the smallest side;
/// for the paper's 15 cm cube that is 8 spheres of 3.75 cm and one of 7.5 cm.
/// Every sphere is contained in the box. Order: grid spheres by x, then y, then z index
/// (x fastest), then the centre sphere.
/// @throws InvalidArgument for a non-positive box size or invalid options.
std::vector<InscribedSphere> InscribedSpheres(const Box& box,
                                              const InscribedSpheresOptions& options = {});

}  // namespace idto
