#include "idto/contact/contact_engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"

namespace idto {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool Matches(const Model& model, const std::string& name, GeometryIndex g) {
  const GeometryInstance& geo = model.geometries()[g];
  return name == "*" || name == geo.name || name == model.body_name(geo.body);
}

bool PairMatches(const Model& model, const std::string& a, const std::string& b, GeometryIndex ga,
                 GeometryIndex gb) {
  return (Matches(model, a, ga) && Matches(model, b, gb)) ||
         (Matches(model, a, gb) && Matches(model, b, ga));
}

void CheckName(const Model& model, const std::string& option, const std::string& name) {
  if (name == "*" || model.HasBody(name)) return;
  for (const GeometryInstance& g : model.geometries()) {
    if (g.name == name) return;
  }
  ThrowInvalidArgument("ContactEngine", option, "\"" + name + "\"",
                       "the name of a geometry or body of model \"" + model.name() + "\", or *");
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

}  // namespace

ContactEngine::ContactEngine(const Model& model, const ContactOptions& options)
    : options_(options) {
  static constexpr const char* kWhere = "ContactEngine";
  options_.parameters.Validate("ContactEngine: options.parameters");
  CheckNonNegative(kWhere, "options.force_tolerance", options_.force_tolerance);
  for (size_t i = 0; i < options_.excluded_pairs.size(); ++i) {
    const std::string key = "options.excluded_pairs[" + std::to_string(i) + "]";
    CheckName(model, key, options_.excluded_pairs[i].first);
    CheckName(model, key, options_.excluded_pairs[i].second);
  }
  for (size_t i = 0; i < options_.included_pairs.size(); ++i) {
    const std::string key = "options.included_pairs[" + std::to_string(i) + "]";
    CheckName(model, key, options_.included_pairs[i].first);
    CheckName(model, key, options_.included_pairs[i].second);
  }
  for (size_t i = 0; i < options_.collision_groups.size(); ++i) {
    for (const std::string& name : options_.collision_groups[i]) {
      CheckName(model, "options.collision_groups[" + std::to_string(i) + "]", name);
    }
  }
  for (size_t i = 0; i < options_.overrides.size(); ++i) {
    const std::string key = "options.overrides[" + std::to_string(i) + "]";
    CheckName(model, key, options_.overrides[i].a);
    CheckName(model, key, options_.overrides[i].b);
  }

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
        has_a = has_a || Matches(model, name, ga);
        has_b = has_b || Matches(model, name, gb);
      }
      if (has_a && has_b) return true;
    }
    return false;
  };

  for (GeometryIndex ga = 0; ga < ng; ++ga) {
    for (GeometryIndex gb = ga + 1; gb < ng; ++gb) {
      const BodyIndex ma = model.mobilized_body(geos[ga].body);
      const BodyIndex mb = model.mobilized_body(geos[gb].body);
      if (ma == mb) continue;  // same rigid body (or both on the world)
      if (IsHalfSpace(geos[ga].shape) && IsHalfSpace(geos[gb].shape)) continue;
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
    for (GeometryIndex g = 0; g < ng; ++g) {
      if (!is_static_bounded(g)) continue;
      // Static: the body is the world or welded to it; its pose is fixed.
      const BodyIndex b = geos[g].body;
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

void ContactEngine::CollectCandidates(const Model& model, const Data& data, ContactData* cd) const {
  (void)model;
  cd->candidates.clear();
  for (int i : other_pairs_) cd->candidates.push_back(i);
  const std::vector<GeometryInstance>& geos = model.geometries();
  for (size_t m = 0; m < moving_with_static_.size(); ++m) {
    const GeometryIndex gm = moving_with_static_[m];
    const Eigen::Vector3d c = data.pose(geos[gm].body) * bound_center_B_[gm];
    const double reach = bound_radius_[gm] + max_cutoff_;
    const std::vector<StaticPartner>& partners = static_partners_[m];
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const BvhNode& node = bvh_[stack[--top]];
      // Distance from c to the box, against the reach.
      const Eigen::Vector3d d =
          (node.lower - c).cwiseMax(Eigen::Vector3d::Zero()).cwiseMax(c - node.upper);
      if (d.squaredNorm() > reach * reach) continue;
      if (node.count == 0) {
        if (top + 2 > 64) {  // never for a balanced tree of < 2^60 items; stay safe
          for (const StaticPartner& sp : partners) cd->candidates.push_back(sp.pair);
          top = 0;
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
        if (it != partners.end() && it->static_geometry == gs) cd->candidates.push_back(it->pair);
      }
    }
  }
  // Evaluate in pair order whatever the traversal order: results are deterministic.
  std::sort(cd->candidates.begin(), cd->candidates.end());
  cd->candidates.erase(std::unique(cd->candidates.begin(), cd->candidates.end()),
                       cd->candidates.end());
}

ContactData ContactEngine::MakeData(const Model& model) const {
  ContactData data;
  data.results.resize(pairs_.size());
  data.F_ext = BodyForces::Zero(6, model.num_bodies());
  data.candidates.reserve(pairs_.size());
  data.result_of_pair.assign(pairs_.size(), -1);
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
  const Eigen::Isometry3d X_WGa = data.X_WB(pair.body_a) * ga.X_BG;
  const Eigen::Isometry3d X_WGb = data.X_WB(pair.body_b) * gb.X_BG;
  const SignedDistanceResult sd = SignedDistance(ga.shape, X_WGa, gb.shape, X_WGb);
  r->pair = i;
  r->phi = sd.distance;
  r->normal_W = sd.normal_W;
  r->exact = sd.exact;
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
      contact_data->F_ext.cols() != model.num_bodies()) {
    ThrowInvalidArgument("ContactEngine::Evaluate", "contact_data",
                         "sized for another engine or model", "ContactEngine::MakeData(model)");
  }
  contact_data->F_ext.setZero();
  contact_data->num_active = 0;
  std::fill(contact_data->result_of_pair.begin(), contact_data->result_of_pair.end(), -1);
  if (use_bvh_) CollectCandidates(model, data, contact_data);
  const int num_candidates =
      use_bvh_ ? static_cast<int>(contact_data->candidates.size()) : num_pairs();
  contact_data->num_pruned = num_pairs() - num_candidates;
  for (int c = 0; c < num_candidates; ++c) {
    const int i = use_bvh_ ? contact_data->candidates[c] : c;
    ContactResult& r = contact_data->results[contact_data->num_active];
    if (!EvaluatePair(model, data, i, &r)) {
      ++contact_data->num_pruned;
      continue;
    }
    contact_data->result_of_pair[i] = contact_data->num_active++;
    AddForces(data, r, &contact_data->F_ext);
  }
}

void ContactEngine::EvaluateChanged(const Model& model, const Data& data,
                                    const ContactData& reference,
                                    const std::vector<char>& body_moved,
                                    ContactData* contact_data) const {
  if (contact_data->results.size() != pairs_.size() || reference.results.size() != pairs_.size() ||
      static_cast<int>(body_moved.size()) != model.num_bodies()) {
    ThrowInvalidArgument("ContactEngine::EvaluateChanged", "contact_data, reference, body_moved",
                         "sized for another engine or model",
                         "ContactEngine::MakeData(model) and num_bodies() flags");
  }
  contact_data->F_ext.setZero();
  contact_data->num_active = 0;
  contact_data->num_pruned = 0;
  std::fill(contact_data->result_of_pair.begin(), contact_data->result_of_pair.end(), -1);
  // Pair order, whether reused or recomputed: the sums are deterministic.
  for (int i = 0; i < num_pairs(); ++i) {
    const ContactPair& pair = pairs_[i];
    ContactResult& r = contact_data->results[contact_data->num_active];
    if (!body_moved[pair.body_a] && !body_moved[pair.body_b]) {
      const int j = reference.result_of_pair[i];
      if (j < 0) {
        ++contact_data->num_pruned;
        continue;
      }
      r = reference.results[j];
    } else if (!EvaluatePair(model, data, i, &r)) {
      ++contact_data->num_pruned;
      continue;
    }
    contact_data->result_of_pair[i] = contact_data->num_active++;
    AddForces(data, r, &contact_data->F_ext);
  }
}

}  // namespace idto
