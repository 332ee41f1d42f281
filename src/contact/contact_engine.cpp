#include "idto/contact/contact_engine.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "idto/core/errors.hpp"
#include "idto/geometry/analytic_distance-inl.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "pair_matching.hpp"

namespace idto {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using contact_internal::CanTouch;
using contact_internal::NameMatches;
using contact_internal::PairMatches;

std::string Quote(const std::string& name) { return "\"" + name + "\""; }

void CheckName(const Model& model, const std::string& option, const std::string& name) {
  const std::string expected = ContactNameProblem(model, name);
  if (!expected.empty()) ThrowInvalidArgument("ContactEngine", option, Quote(name), expected);
}

// Bounding sphere of a shape about its frame origin (infinite for a half-space).
double BoundingRadius(const Shape& shape) {
  if (const auto* s = std::get_if<Sphere>(&shape)) return s->radius;
  if (const auto* c = std::get_if<Capsule>(&shape)) return c->radius + 0.5 * c->length;
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    return std::hypot(c->radius, 0.5 * c->length);
  }
  if (const auto* b = std::get_if<Box>(&shape)) return 0.5 * b->size.norm();
  return kInf;
}

bool IsHalfSpace(const Shape& shape) { return std::holds_alternative<HalfSpace>(shape); }

// A distinct id per constructed engine (copies keep it: they have the same pairs).
std::uint64_t NextEngineId() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

ContactEngine::ContactEngine(const Model& model, const ContactOptions& options)
    : options_(options), id_(NextEngineId()) {
  ValidateOptions(model);
  DecidePairs(model);
  ValidateOverrides(model);
  SetUpBroadPhase(model);
}

void ContactEngine::ValidateOptions(const Model& model) const {
  static constexpr const char* kWhere = "ContactEngine";
  options_.parameters.Validate("ContactEngine: options.parameters");
  CheckNonNegative(kWhere, "options.force_tolerance", options_.force_tolerance);
  auto check_pairs = [&](const std::string& field,
                         const std::vector<std::pair<std::string, std::string>>& pairs) {
    for (size_t i = 0; i < pairs.size(); ++i) {
      const std::string key = "options." + field + "[" + std::to_string(i) + "]";
      CheckName(model, key + "[0]", pairs[i].first);
      CheckName(model, key + "[1]", pairs[i].second);
    }
  };
  check_pairs("excluded_pairs", options_.excluded_pairs);
  check_pairs("included_pairs", options_.included_pairs);
  for (size_t i = 0; i < options_.included_pairs.size(); ++i) {
    const auto& [a, b] = options_.included_pairs[i];
    const std::string expected = IncludedPairProblem(model, a, b);
    if (!expected.empty()) {
      ThrowInvalidArgument(kWhere, "options.included_pairs[" + std::to_string(i) + "]",
                           "[" + a + ", " + b + "]", expected);
    }
  }
  for (size_t i = 0; i < options_.collision_groups.size(); ++i) {
    const std::vector<std::string>& group = options_.collision_groups[i];
    const std::string key = "options.collision_groups[" + std::to_string(i) + "]";
    const std::string expected = CollisionGroupProblem(group.size());
    if (!expected.empty()) {
      ThrowInvalidArgument(
          kWhere, key, group.empty() ? "an empty list" : "a list of one name " + Quote(group[0]),
          expected);
    }
    for (size_t j = 0; j < group.size(); ++j) {
      CheckName(model, key + "[" + std::to_string(j) + "]", group[j]);
    }
  }
  for (size_t i = 0; i < options_.overrides.size(); ++i) {
    const std::string key = "options.overrides[" + std::to_string(i) + "]";
    CheckName(model, key + ".a", options_.overrides[i].a);
    CheckName(model, key + ".b", options_.overrides[i].b);
  }
}

void ContactEngine::ValidateOverrides(const Model& model) const {
  for (size_t i = 0; i < options_.overrides.size(); ++i) {
    const ContactParameterOverride& o = options_.overrides[i];
    const std::string expected = ContactOverrideProblem(model, pairs_, o.a, o.b, "the options'");
    if (!expected.empty()) {
      ThrowInvalidArgument("ContactEngine", "options.overrides[" + std::to_string(i) + "]",
                           "[" + o.a + ", " + o.b + "]", expected);
    }
  }
}

void ContactEngine::DecidePairs(const Model& model) {
  const std::vector<GeometryInstance>& geos = model.geometries();
  const int ng = static_cast<int>(geos.size());
  bound_center_B_.resize(ng);
  bound_radius_.resize(ng);
  for (int g = 0; g < ng; ++g) {
    bound_center_B_[g] = geos[g].X_BG.translation();
    bound_radius_[g] = BoundingRadius(geos[g].shape);
  }

  auto in_same_group = [&](GeometryIndex ga, GeometryIndex gb) {
    for (const std::vector<std::string>& group : options_.collision_groups) {
      bool has_a = false, has_b = false;
      for (const std::string& name : group) {
        has_a = has_a || NameMatches(model, name, ga);
        has_b = has_b || NameMatches(model, name, gb);
      }
      if (has_a && has_b) return true;
    }
    return false;
  };

  for (GeometryIndex ga = 0; ga < ng; ++ga) {
    for (GeometryIndex gb = ga + 1; gb < ng; ++gb) {
      // Never two geometries on one rigid body (or both on the world), nor two half-spaces.
      if (!CanTouch(model, ga, gb)) continue;
      const BodyIndex ma = model.mobilized_body(geos[ga].body);
      const BodyIndex mb = model.mobilized_body(geos[gb].body);
      // Bodies joined by a 1-DoF joint usually overlap at the joint: skip them. Bodies on
      // floating or planar joints move freely with respect to their parent (a ball on the
      // ground): keep them.
      auto hinged_to = [&](BodyIndex child, BodyIndex parent) {
        if (child == kWorldBody || model.moving_parent(child) != parent) return false;
        const JointType t = model.joint_type(child);
        return t != JointType::kFloating && t != JointType::kPlanar;
      };
      const bool adjacent = hinged_to(ma, mb) || hinged_to(mb, ma);
      bool included = !adjacent;
      if (!options_.included_pairs.empty()) {
        included = false;
        for (const auto& [a, b] : options_.included_pairs) {
          if (PairMatches(model, a, b, ga, gb)) included = true;
        }
      }
      if (!included) continue;
      bool excluded = false;
      for (const auto& [a, b] : options_.excluded_pairs) {
        if (PairMatches(model, a, b, ga, gb)) excluded = true;
      }
      if (excluded || in_same_group(ga, gb)) continue;

      ContactPair pair;
      // Half-spaces go first so that A is the ground in ground contacts (normal +z).
      const bool swap = IsHalfSpace(geos[gb].shape);
      pair.geometry_a = swap ? gb : ga;
      pair.geometry_b = swap ? ga : gb;
      pair.body_a = geos[pair.geometry_a].body;
      pair.body_b = geos[pair.geometry_b].body;
      pair.parameters = options_.parameters;
      for (const ContactParameterOverride& o : options_.overrides) {
        if (!PairMatches(model, o.a, o.b, ga, gb)) continue;
        ContactParameters& p = pair.parameters;
        if (o.stiffness) p.stiffness = *o.stiffness;
        if (o.smoothing) p.smoothing = *o.smoothing;
        if (o.dissipation_velocity) p.dissipation_velocity = *o.dissipation_velocity;
        if (o.friction_coefficient) p.friction_coefficient = *o.friction_coefficient;
        if (o.stiction_velocity) p.stiction_velocity = *o.stiction_velocity;
      }
      pair.parameters.Validate("ContactEngine: parameters of pair (\"" + geos[ga].name + "\", \"" +
                               geos[gb].name + "\")");
      pair.cutoff_distance = options_.force_tolerance > 0.0
                                 ? ContactCutoffDistance(pair.parameters, options_.force_tolerance)
                                 : kInf;
      pairs_.push_back(pair);
    }
  }
}

void ContactEngine::SetUpBroadPhase(const Model& model) {
  const std::vector<GeometryInstance>& geos = model.geometries();
  const int ng = static_cast<int>(geos.size());
  // Broad phase: pairs (static bounded geometry, moving geometry) go through a hierarchy when
  // pruning is on and there are enough of them to matter.
  int num_static_pairs = 0;
  auto is_static_bounded = [&](GeometryIndex g) {
    return model.mobilized_body(geos[g].body) == kWorldBody && !IsHalfSpace(geos[g].shape);
  };
  for (const ContactPair& p : pairs_) {
    if (is_static_bounded(p.geometry_a) || is_static_bounded(p.geometry_b)) ++num_static_pairs;
    max_cutoff_ = std::max(max_cutoff_, p.cutoff_distance);
  }
  use_bvh_ = options_.force_tolerance > 0.0 && num_static_pairs >= 16 && max_cutoff_ < kInf;
  if (use_bvh_) {
    static_center_W_.assign(ng, Eigen::Vector3d::Zero());
    std::vector<int> partner_slot(ng, -1);
    for (int i = 0; i < num_pairs(); ++i) {
      const ContactPair& p = pairs_[i];
      const bool sa = is_static_bounded(p.geometry_a), sb = is_static_bounded(p.geometry_b);
      if (!sa && !sb) {
        other_pairs_.push_back(i);
        continue;
      }
      const GeometryIndex gs = sa ? p.geometry_a : p.geometry_b;
      const GeometryIndex gm = sa ? p.geometry_b : p.geometry_a;
      if (partner_slot[gm] < 0) {
        partner_slot[gm] = static_cast<int>(moving_with_static_.size());
        moving_with_static_.push_back(gm);
        static_partners_.emplace_back();
      }
      static_partners_[partner_slot[gm]].push_back(StaticPartner{gs, i});
    }
    for (auto& list : static_partners_) {
      std::sort(list.begin(), list.end(), [](const StaticPartner& x, const StaticPartner& y) {
        return x.static_geometry < y.static_geometry;
      });
    }
    for (GeometryIndex gm : moving_with_static_) {
      query_body_.push_back(geos[gm].body);
      query_center_B_.push_back(bound_center_B_[gm]);
    }
    pair_in_bvh_.assign(pairs_.size(), 0);
    for (const std::vector<StaticPartner>& list : static_partners_) {
      for (const StaticPartner& sp : list) pair_in_bvh_[sp.pair] = 1;
    }
    for (GeometryIndex g = 0; g < ng; ++g) {
      if (!is_static_bounded(g)) continue;
      // Static: the body is the world or welded to it; its pose is fixed.
      const BodyIndex b = geos[g].body;
      if (std::find(static_bodies_.begin(), static_bodies_.end(), b) == static_bodies_.end()) {
        static_bodies_.push_back(b);
      }
      const RigidTransform& X_WB = model.X_MB(b);  // the world is the mobilized body
      static_center_W_[g] = X_WB * bound_center_B_[g];
      bvh_items_.push_back(g);
    }
    bvh_.reserve(2 * bvh_items_.size());
    BuildBvh(0, static_cast<int>(bvh_items_.size()));
  }
}

int ContactEngine::BuildBvh(int first, int count) {
  BvhNode node;
  node.lower = Eigen::Vector3d::Constant(kInf);
  node.upper = Eigen::Vector3d::Constant(-kInf);
  for (int i = first; i < first + count; ++i) {
    const GeometryIndex g = bvh_items_[i];
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(bound_radius_[g]);
    node.lower = node.lower.cwiseMin(static_center_W_[g] - r);
    node.upper = node.upper.cwiseMax(static_center_W_[g] + r);
  }
  const int index = static_cast<int>(bvh_.size());
  bvh_.push_back(node);
  if (count <= 4) {
    bvh_[index].first = first;
    bvh_[index].count = count;
    return index;
  }
  // Median split along the longest axis of the centres (deterministic: ties by index).
  int axis;
  (node.upper - node.lower).maxCoeff(&axis);
  auto begin = bvh_items_.begin() + first;
  std::nth_element(begin, begin + count / 2, begin + count, [&](GeometryIndex x, GeometryIndex y) {
    const double cx = static_center_W_[x](axis), cy = static_center_W_[y](axis);
    return cx < cy || (cx == cy && x < y);
  });
  const int left = BuildBvh(first, count / 2);
  const int right = BuildBvh(first + count / 2, count - count / 2);
  bvh_[index].left = left;
  bvh_[index].right = right;
  return index;
}

Eigen::Vector3d ContactEngine::MovingCenter(const Data& data, int m) const {
  return data.pose(query_body_[m]) * query_center_B_[m];
}

bool ContactEngine::BroadPhaseHolds(const Data& data, const ContactData& record,
                                    const std::vector<char>* body_moved) const {
  const size_t num_queries = moving_with_static_.size();
  if (record.broad_phase_owner != id_ || record.broad_phase_center.size() != num_queries ||
      record.broad_phase_clearance.size() != num_queries) {
    return false;
  }
  for (size_t m = 0; m < num_queries; ++m) {
    if (body_moved != nullptr && !(*body_moved)[query_body_[m]]) continue;
    const double clearance = record.broad_phase_clearance[m];
    const Eigen::Vector3d c = MovingCenter(data, static_cast<int>(m));
    if (!((c - record.broad_phase_center[m]).squaredNorm() < clearance * clearance)) return false;
  }
  return true;
}

void ContactEngine::QueryStatic(const Data& data, int m, std::vector<int>* candidates,
                                Eigen::Vector3d* center, double* clearance) const {
  const GeometryIndex gm = moving_with_static_[m];
  const Eigen::Vector3d c = MovingCenter(data, m);
  const double reach = bound_radius_[gm] + max_cutoff_;
  const double reach2 = reach * reach;
  const std::vector<StaticPartner>& partners = static_partners_[m];
  const size_t start = candidates->size();
  double min_rejected2 = kInf;  // squared distance to the nearest rejected box
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = bvh_[stack[--top]];
    // Distance from c to the box, against the reach.
    const Eigen::Vector3d d =
        (node.lower - c).cwiseMax(Eigen::Vector3d::Zero()).cwiseMax(c - node.upper);
    const double d2 = d.squaredNorm();
    if (d2 > reach2) {
      min_rejected2 = std::min(min_rejected2, d2);
      continue;
    }
    if (node.count == 0) {
      if (top + 2 > 64) {  // never for a balanced tree of < 2^60 items; stay safe
        // Every partner, once: drop what this query has pushed so far.
        candidates->resize(start);
        for (const StaticPartner& sp : partners) candidates->push_back(sp.pair);
        min_rejected2 = kInf;
        break;
      }
      stack[top++] = node.left;
      stack[top++] = node.right;
      continue;
    }
    for (int i = node.first; i < node.first + node.count; ++i) {
      const GeometryIndex gs = bvh_items_[i];
      const auto it = std::lower_bound(
          partners.begin(), partners.end(), gs,
          [](const StaticPartner& sp, GeometryIndex g) { return sp.static_geometry < g; });
      if (it != partners.end() && it->static_geometry == gs) candidates->push_back(it->pair);
    }
  }
  if (center != nullptr) *center = c;
  // Every rejected box stays rejected while c moves less than this (the 1e-9 margin covers
  // round-off), so the partners found are a superset of what a query from there would find.
  if (clearance != nullptr) *clearance = (std::sqrt(min_rejected2) - reach) * (1.0 - 1e-9);
}

void ContactEngine::CollectCandidates(const Data& data, ContactData* cd) const {
  // Temporal coherence: when this ContactData's last broad phase still holds (every moving
  // geometry moved less than its clearance since, as between a solver's nearby iterates), its
  // candidates are still a superset of the pairs within reach.
  if (BroadPhaseHolds(data, *cd, nullptr)) return;
  cd->candidates.clear();
  for (int i : other_pairs_) cd->candidates.push_back(i);
  const bool record = cd->broad_phase_center.size() == moving_with_static_.size() &&
                      cd->broad_phase_clearance.size() == moving_with_static_.size();
  for (size_t m = 0; m < moving_with_static_.size(); ++m) {
    QueryStatic(data, static_cast<int>(m), &cd->candidates,
                record ? &cd->broad_phase_center[m] : nullptr,
                record ? &cd->broad_phase_clearance[m] : nullptr);
  }
  // Evaluate in pair order whatever the traversal order: results are deterministic. Each pair
  // is pushed at most once (a static geometry sits in one leaf).
  std::sort(cd->candidates.begin(), cd->candidates.end());
  cd->broad_phase_owner = record ? id_ : 0;
}

void ContactEngine::ResetResults(ContactData* cd) const {
  cd->F_ext.setZero();
  // Only the entries of the last evaluation's results are set (cheaper than clearing all pairs
  // when most are pruned); a ContactData whose count is out of range is cleared in full.
  const int n = static_cast<int>(cd->result_of_pair.size());
  bool consistent = cd->num_active >= 0 && cd->num_active <= static_cast<int>(cd->results.size());
  for (int c = 0; consistent && c < cd->num_active; ++c) {
    const int pair = cd->results[c].pair;
    if (pair < 0 || pair >= n) {
      consistent = false;
    } else {
      cd->result_of_pair[pair] = -1;
    }
  }
  if (!consistent) std::fill(cd->result_of_pair.begin(), cd->result_of_pair.end(), -1);
  cd->num_active = 0;
  cd->num_pruned = 0;
}

ContactData ContactEngine::MakeData(const Model& model) const {
  ContactData data;
  data.results.resize(pairs_.size());
  data.F_ext = BodyForces::Zero(6, model.num_bodies());
  data.candidates.reserve(pairs_.size());
  data.result_of_pair.assign(pairs_.size(), -1);
  data.broad_phase_center.assign(moving_with_static_.size(), Eigen::Vector3d::Zero());
  data.broad_phase_clearance.assign(moving_with_static_.size(), 0.0);
  data.broad_phase_owner = 0;
  return data;
}

bool ContactEngine::EvaluatePair(const Model& model, const Data& data, int i,
                                 ContactResult* r) const {
  const std::vector<GeometryInstance>& geos = model.geometries();
  const ContactPair& pair = pairs_[i];
  const GeometryInstance& ga = geos[pair.geometry_a];
  const GeometryInstance& gb = geos[pair.geometry_b];
  const RigidTransform& X_WA = data.pose(pair.body_a);
  const RigidTransform& X_WB = data.pose(pair.body_b);
  if (pair.cutoff_distance < kInf) {
    // A lower bound on phi from bounding spheres (B is never a half-space).
    const Eigen::Vector3d c_B = X_WB * bound_center_B_[pair.geometry_b];
    double lower_bound;
    if (IsHalfSpace(ga.shape)) {
      const Eigen::Vector3d n_W = X_WA.R * ga.X_BG.linear().col(2);
      const Eigen::Vector3d p_W = X_WA * Eigen::Vector3d(ga.X_BG.translation());
      lower_bound = n_W.dot(c_B - p_W) - bound_radius_[pair.geometry_b];
    } else {
      const Eigen::Vector3d c_A = X_WA * bound_center_B_[pair.geometry_a];
      lower_bound =
          (c_B - c_A).norm() - bound_radius_[pair.geometry_a] - bound_radius_[pair.geometry_b];
    }
    if (lower_bound > pair.cutoff_distance) return false;
  }
  r->pair = i;
  // Analytic pairs straight through the pair code on the body poses (no Isometry round trip
  // and no argument checks: the shapes were checked when the model was built, and a
  // non-finite pose gives a non-finite result, which the solver rejects as a step).
  SignedDistanceResultTpl<double> sd;
  const Sphere* sphere_a = std::get_if<Sphere>(&ga.shape);
  const Sphere* sphere_b = std::get_if<Sphere>(&gb.shape);
  if (sphere_a != nullptr && sphere_b != nullptr) {
    // Two spheres need only their centres: the same arithmetic as the geometry poses' origins,
    // without their rotations (many pairs per step on the bi-manual and Allegro scenes).
    const Eigen::Vector3d t_a = ga.X_BG.translation(), t_b = gb.X_BG.translation();
    sd = internal::SpherePair<double>(X_WA * t_a, sphere_a->radius, X_WB * t_b, sphere_b->radius,
                                      Eigen::Vector3d::UnitZ());
    r->exact = true;
  } else {
    const RigidTransform X_WGa = X_WA * RigidTransform(ga.X_BG.linear(), ga.X_BG.translation());
    const RigidTransform X_WGb = X_WB * RigidTransform(gb.X_BG.linear(), gb.X_BG.translation());
    r->exact = AnalyticSignedDistance<double>(ga.shape, X_WGa, gb.shape, X_WGb, &sd);
  }
  if (!r->exact) {
    const SignedDistanceResult fcl = SignedDistance(ga.shape, data.X_WB(pair.body_a) * ga.X_BG,
                                                    gb.shape, data.X_WB(pair.body_b) * gb.X_BG);
    sd.distance = fcl.distance;
    sd.normal_W = fcl.normal_W;
    sd.p_WA = fcl.p_WA;
    sd.p_WB = fcl.p_WB;
  }
  r->phi = sd.distance;
  r->normal_W = sd.normal_W;
  r->p_WC = 0.5 * (sd.p_WA + sd.p_WB);
  // Velocity of C moving with B relative to C moving with A.
  const Eigen::Vector3d v_WCb =
      data.v_WBo(pair.body_b) + data.w_WB(pair.body_b).cross(r->p_WC - X_WB.p);
  const Eigen::Vector3d v_WCa =
      data.v_WBo(pair.body_a) + data.w_WB(pair.body_a).cross(r->p_WC - X_WA.p);
  const Eigen::Vector3d v_c = v_WCb - v_WCa;
  r->vn = r->normal_W.dot(v_c);
  r->vt = v_c - r->vn * r->normal_W;
  r->force = CalcContactForce(pair.parameters, r->phi, r->vn, r->vt, r->normal_W);
  return true;
}

void ContactEngine::AddForces(const Data& data, const ContactResult& r, BodyForces* F) const {
  const ContactPair& pair = pairs_[r.pair];
  const Eigen::Vector3d& f = r.force.f;
  auto F_b = F->col(pair.body_b);
  F_b.head<3>() += (r.p_WC - data.pose(pair.body_b).p).cross(f);
  F_b.tail<3>() += f;
  auto F_a = F->col(pair.body_a);
  F_a.head<3>() -= (r.p_WC - data.pose(pair.body_a).p).cross(f);
  F_a.tail<3>() -= f;
}

void ContactEngine::Evaluate(const Model& model, const Data& data,
                             ContactData* contact_data) const {
  if (contact_data->results.size() != pairs_.size() ||
      contact_data->result_of_pair.size() != pairs_.size() ||
      contact_data->F_ext.cols() != model.num_bodies()) {
    ThrowInvalidArgument("ContactEngine::Evaluate", "contact_data",
                         "sized for another engine or model", "ContactEngine::MakeData(model)");
  }
  ResetResults(contact_data);
  if (use_bvh_) {
    CollectCandidates(data, contact_data);
  } else {
    contact_data->broad_phase_owner = 0;
  }
  const int num_candidates =
      use_bvh_ ? static_cast<int>(contact_data->candidates.size()) : num_pairs();
  for (int c = 0; c < num_candidates; ++c) {
    const int i = use_bvh_ ? contact_data->candidates[c] : c;
    ContactResult& r = contact_data->results[contact_data->num_active];
    if (!EvaluatePair(model, data, i, &r)) continue;
    contact_data->result_of_pair[i] = contact_data->num_active++;
    AddForces(data, r, &contact_data->F_ext);
  }
  contact_data->num_pruned = num_pairs() - contact_data->num_active;
}

void ContactEngine::EvaluateChanged(const Model& model, const Data& data,
                                    const ContactData& reference,
                                    const std::vector<char>& body_moved,
                                    ContactData* contact_data) const {
  if (contact_data->results.size() != pairs_.size() ||
      contact_data->result_of_pair.size() != pairs_.size() ||
      reference.results.size() != pairs_.size() ||
      reference.result_of_pair.size() != pairs_.size() ||
      static_cast<int>(body_moved.size()) != model.num_bodies()) {
    ThrowInvalidArgument("ContactEngine::EvaluateChanged", "contact_data, reference, body_moved",
                         "sized for another engine or model",
                         "ContactEngine::MakeData(model) and num_bodies() flags");
  }
  ResetResults(contact_data);
  int num_candidates = num_pairs();
  const std::vector<int>* candidates = &contact_data->candidates;
  contact_data->broad_phase_owner = 0;  // its candidates are not an Evaluate's broad phase
  if (use_bvh_) {
    bool static_moved = false;  // only if the caller flags a static body
    for (BodyIndex b : static_bodies_) static_moved = static_moved || body_moved[b] != 0;
    // When the reference's broad phase still holds for every moved geometry (it moved less
    // than its clearance, as under a finite-difference perturbation), the reference's
    // candidates are a superset of the pairs that can be active: every pair outside the
    // hierarchy, the static pairs of the moved geometries that a query from here could find,
    // and the reference's active pairs. Nothing to query.
    const bool reuse = !static_moved && BroadPhaseHolds(data, reference, &body_moved);
    if (reuse) {
      candidates = &reference.candidates;
    } else {
      // The pairs that can be active, each once: every pair outside the hierarchy; the static
      // partners of moved geometries that the hierarchy finds; and the active static pairs of
      // the reference whose bodies did not move (reused below). Disjoint lists, so at most
      // num_pairs() entries: the reserved capacity, no allocation.
      std::vector<int>& list = contact_data->candidates;
      list.clear();
      for (int i : other_pairs_) list.push_back(i);
      for (size_t m = 0; m < moving_with_static_.size(); ++m) {
        if (static_moved || body_moved[query_body_[m]]) {
          QueryStatic(data, static_cast<int>(m), &list, nullptr, nullptr);
        }
      }
      for (int c = 0; c < reference.num_active && !static_moved; ++c) {
        const int i = reference.results[c].pair;
        const ContactPair& pair = pairs_[i];
        if (pair_in_bvh_[i] && !body_moved[pair.body_a] && !body_moved[pair.body_b]) {
          list.push_back(i);
        }
      }
      std::sort(list.begin(), list.end());
    }
    num_candidates = static_cast<int>(candidates->size());
  }
  // Pair order, whether reused or recomputed: the sums are deterministic.
  for (int c = 0; c < num_candidates; ++c) {
    const int i = use_bvh_ ? (*candidates)[c] : c;
    const ContactPair& pair = pairs_[i];
    ContactResult& r = contact_data->results[contact_data->num_active];
    if (!body_moved[pair.body_a] && !body_moved[pair.body_b]) {
      const int j = reference.result_of_pair[i];
      if (j < 0) continue;
      r = reference.results[j];
    } else if (!EvaluatePair(model, data, i, &r)) {
      continue;
    }
    contact_data->result_of_pair[i] = contact_data->num_active++;
    AddForces(data, r, &contact_data->F_ext);
  }
  contact_data->num_pruned = num_pairs() - contact_data->num_active;
}

}  // namespace idto
