#pragma once

/// @file
/// Contact on a Model: which geometry pairs can touch (decided once), and per-thread evaluation
/// of signed distances, contact velocities, forces and the resulting body forces for RNEA.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_law.hpp"
#include "idto/core/types.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Overrides some contact parameters for the pairs matching (a, b) in either order. A name
/// matches a geometry when it equals the geometry's name or its body's name (the geometry
/// attached to that body, not to the bodies welded to it); "*" matches any. An override must
/// match at least one pair the ContactEngine evaluates (ContactOverrideProblem).
struct ContactParameterOverride {
  std::string a;
  std::string b;
  std::optional<double> stiffness;
  std::optional<double> smoothing;
  std::optional<double> dissipation_velocity;
  std::optional<double> friction_coefficient;
  std::optional<double> stiction_velocity;
};

/// Which pairs can touch, their parameters, and pruning.
///
/// Every filter and override must take effect: a name must be "*", a geometry's name or the
/// name of a body with collision geometry of its own (ContactNameProblem); a collision group
/// needs at least two names (CollisionGroupProblem); an included pair must match two geometries
/// that can touch (IncludedPairProblem); an override must match a pair that is evaluated
/// (ContactOverrideProblem). Exclusions of pairs that never touch anyway are accepted (what they
/// ask for holds). ContactEngine's constructor checks all of them.
struct ContactOptions {
  /// The law's parameters for every pair, unless overridden.
  ContactParameters parameters;
  /// Per-pair overrides, applied in order (later ones win).
  std::vector<ContactParameterOverride> overrides;
  /// Pairs (a, b) never evaluated; names as in ContactParameterOverride.
  std::vector<std::pair<std::string, std::string>> excluded_pairs;
  /// Collision groups: lists of geometry or body names; pairs whose two geometries are in the
  /// same group are not evaluated (e.g. all links of one hand).
  std::vector<std::vector<std::string>> collision_groups;
  /// When non-empty, only pairs matching one of these are evaluated (an explicit include may
  /// also re-enable a pair between a parent and child body).
  std::vector<std::pair<std::string, std::string>> included_pairs;
  /// Pairs whose compliance force c(phi) is certainly below this (N) are skipped, using a cheap
  /// bounding-sphere lower bound on phi against ContactCutoffDistance(). 0 disables pruning.
  double force_tolerance{1e-8};
};

/// One pair that can touch, fixed for the life of a ContactEngine.
struct ContactPair {
  GeometryIndex geometry_a{0};
  GeometryIndex geometry_b{0};
  BodyIndex body_a{0};
  BodyIndex body_b{0};
  ContactParameters parameters;
  /// Pruning distance: beyond it the pair is skipped (+inf when pruning is off).
  double cutoff_distance{0.0};
};

/// The checks behind ContactEngine's refusal of filters and overrides that would have no effect,
/// one entry at a time (the YAML loader calls them to name the key and line of an entry). Each
/// returns what was expected, with the reason the entry would be lost, or an empty string when
/// the entry takes effect.

/// A name of a filter or override: "*", a geometry's name, or the name of a body with collision
/// geometry of its own (a body name stands for the geometry attached to that body, not to the
/// bodies welded to it, so a body without geometry would match nothing).
std::string ContactNameProblem(const Model& model, const std::string& name);

/// A collision group of `num_names` names: at least two (pairs within a group are not evaluated;
/// one name leaves out only pairs on one body, which never touch anyway).
std::string CollisionGroupProblem(std::size_t num_names);

/// An included pair (a, b): it must match two geometries that can touch (on different rigid
/// bodies, not both half-spaces); otherwise it includes nothing.
std::string IncludedPairProblem(const Model& model, const std::string& a, const std::string& b);

/// An override of the pairs (a, b): it must match one of `pairs`, the pairs of a ContactEngine
/// built on `model` with the same filters (its parameters do not change which pairs are
/// evaluated). `filters` names the filters in the message (e.g. "the options'" or
/// "scene.contact's").
std::string ContactOverrideProblem(const Model& model, const std::vector<ContactPair>& pairs,
                                   const std::string& a, const std::string& b,
                                   const std::string& filters);

/// One evaluated pair.
struct ContactResult {
  int pair{0};                                         ///< index into ContactEngine::pairs()
  double phi{0.0};                                     ///< signed distance, m
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};  ///< unit, from A to B
  Eigen::Vector3d p_WC{Eigen::Vector3d::Zero()};       ///< contact point (midpoint of witnesses)
  double vn{0.0};                               ///< normal relative velocity (B relative to A), m/s
  Eigen::Vector3d vt{Eigen::Vector3d::Zero()};  ///< tangential relative velocity, m/s
  ContactForce force;                           ///< force on B at C (A receives the opposite)
  bool exact{true};  ///< false when the distance came from FCL (approximate)
};

/// Per-thread buffers for EvaluateContacts; nothing is allocated during an evaluation.
struct ContactData {
  /// Results of the evaluated (non-pruned) pairs: entries [0, num_active).
  std::vector<ContactResult> results;
  int num_active{0};
  /// Number of pairs skipped by pruning in the last evaluation.
  int num_pruned{0};
  /// Spatial contact forces on every body at its origin, world frame (6 x num_bodies), the
  /// input InverseDynamics takes as external forces.
  BodyForces F_ext;
  /// Scratch: candidate pairs of the broad phase (capacity: the number of pairs).
  std::vector<int> candidates;
  /// For each pair: its entry in `results`, or -1 when it was pruned (num_pairs()).
  std::vector<int> result_of_pair;
  /// The broad phase recorded by the last Evaluate (static geometry through the hierarchy):
  /// for each moving geometry with static partners, the centre of its bounding sphere and how
  /// far that centre may move before the static pairs in `candidates` may no longer cover every
  /// pair within the cut-off. EvaluateChanged reuses it when this is its reference, and the
  /// next Evaluate into this ContactData while it still holds.
  std::vector<Eigen::Vector3d> broad_phase_center;
  std::vector<double> broad_phase_clearance;
  /// Id of the engine that recorded the broad phase above (0: none; EvaluateChanged and
  /// engines without the hierarchy record none).
  std::uint64_t broad_phase_owner{0};
};

/// The immutable contact description of a Model: the list of pairs that can touch.
class ContactEngine {
 public:
  /// Decides the pairs once: never two geometries on the same (welded) body, both on the
  /// world, two half-spaces, or a parent and a child body joined by a 1-DoF joint (bodies on
  /// floating or planar joints do touch their parent, e.g. a ball on the ground); then the
  /// options' filters.
  /// Throws InvalidArgument naming the option field and entry (e.g. options.overrides[2]), the
  /// value and what was expected on invalid parameters and on filters or overrides that would
  /// have no effect (see ContactOptions): unknown names, bodies without collision geometry,
  /// groups of fewer than two names, included pairs that match no two geometries that can touch,
  /// overrides that match no evaluated pair.
  ContactEngine(const Model& model, const ContactOptions& options);

  const std::vector<ContactPair>& pairs() const { return pairs_; }
  int num_pairs() const { return static_cast<int>(pairs_.size()); }
  const ContactOptions& options() const { return options_; }
  /// Buffers sized for this engine and model.
  ContactData MakeData(const Model& model) const;

  /// Evaluates every pair that is not pruned. `data` must hold ForwardKinematics(q, v). Fills
  /// contact_data->results and F_ext. Allocation-free.
  void Evaluate(const Model& model, const Data& data, ContactData* contact_data) const;

  /// As Evaluate, but pairs whose two bodies are not flagged in `body_moved` (num_bodies()
  /// entries) take their result from `reference`, an evaluation of this engine at a state where
  /// those bodies had the same poses and velocities (the solver's finite differences: perturbing
  /// one coordinate moves only the bodies downstream of its joint). Results, forces and their
  /// order are those Evaluate would give, up to the pruning decisions of reused pairs. Pairs
  /// against static geometry go through the same broad phase as in Evaluate, so the cost of a
  /// call grows with the pairs near the moved bodies, not with all pairs. Allocation-free.
  void EvaluateChanged(const Model& model, const Data& data, const ContactData& reference,
                       const std::vector<char>& body_moved, ContactData* contact_data) const;

 private:
  ContactOptions options_;
  std::uint64_t id_{0};  // distinct per constructed engine, for ContactData::broad_phase_owner
  std::vector<ContactPair> pairs_;
  // Per geometry: bounding-sphere centre in its body frame and radius (inf for half-spaces).
  std::vector<Eigen::Vector3d> bound_center_B_;
  std::vector<double> bound_radius_;

  // Broad phase for pairs between a moving geometry and a bounded static (world) geometry: a
  // bounding-volume hierarchy over the static geometries' fixed bounding spheres, queried once
  // per moving geometry, instead of one bound test per pair.
  struct BvhNode {
    Eigen::Vector3d lower, upper;  // AABB of the bounding spheres below
    int first{0}, count{0};        // leaf: range in bvh_items_; inner: count = 0
    int left{-1}, right{-1};
  };
  struct StaticPartner {
    GeometryIndex static_geometry;
    int pair;
  };
  std::vector<BvhNode> bvh_;
  std::vector<GeometryIndex> bvh_items_;
  std::vector<Eigen::Vector3d> static_center_W_;  // per geometry (static ones only)
  // Per moving geometry with static partners: its partners sorted by static geometry index.
  std::vector<GeometryIndex> moving_with_static_;
  // Per entry of moving_with_static_: its body and bounding-sphere centre in that body.
  std::vector<BodyIndex> query_body_;
  std::vector<Eigen::Vector3d> query_center_B_;
  std::vector<std::vector<StaticPartner>> static_partners_;
  std::vector<int> other_pairs_;          // pairs not handled by the hierarchy, in order
  std::vector<char> pair_in_bvh_;         // per pair: handled by the hierarchy
  std::vector<BodyIndex> static_bodies_;  // bodies carrying the hierarchy's static geometry
  double max_cutoff_{0.0};
  bool use_bvh_{false};

  // The constructor's steps: the filters checked against the model; the pairs that can touch
  // (with their parameters and cut-off distances); the overrides checked against those pairs;
  // the broad phase over static geometry.
  void ValidateOptions(const Model& model) const;
  void DecidePairs(const Model& model);
  void ValidateOverrides(const Model& model) const;
  void SetUpBroadPhase(const Model& model);
  int BuildBvh(int first, int count);
  // World-frame centre of the bounding sphere of moving geometry moving_with_static_[m].
  Eigen::Vector3d MovingCenter(const Data& data, int m) const;
  // Whether `record` holds a broad phase of this engine that is still valid at `data`: every
  // moving geometry (only those on bodies flagged in *body_moved, when given) moved less than
  // its clearance.
  bool BroadPhaseHolds(const Data& data, const ContactData& record,
                       const std::vector<char>* body_moved) const;
  // Appends the static partners of moving geometry moving_with_static_[m] that the hierarchy
  // cannot exclude (each at most once). When given, *center receives the query's centre and
  // *clearance how far it may move with the answer still a superset of the pairs in reach.
  void QueryStatic(const Data& data, int m, std::vector<int>* candidates, Eigen::Vector3d* center,
                   double* clearance) const;
  // Zeroes F_ext and the counts and clears result_of_pair's entries of the last results.
  void ResetResults(ContactData* cd) const;
  bool EvaluatePair(const Model& model, const Data& data, int i, ContactResult* r) const;
  void AddForces(const Data& data, const ContactResult& r, BodyForces* F) const;
  void CollectCandidates(const Data& data, ContactData* cd) const;
};

}  // namespace idto
