// The checks that refuse ContactOptions filters and overrides that would have no effect
// (idto/contact/contact_engine.hpp), shared by ContactEngine and the YAML loader.

#include <string>
#include <variant>
#include <vector>

#include "idto/contact/contact_engine.hpp"
#include "pair_matching.hpp"

namespace idto {

namespace contact_internal {

bool NameMatches(const Model& model, const std::string& name, GeometryIndex g) {
  const GeometryInstance& geo = model.geometries()[g];
  return name == "*" || name == geo.name || name == model.body_name(geo.body);
}

bool PairMatches(const Model& model, const std::string& a, const std::string& b, GeometryIndex ga,
                 GeometryIndex gb) {
  return (NameMatches(model, a, ga) && NameMatches(model, b, gb)) ||
         (NameMatches(model, a, gb) && NameMatches(model, b, ga));
}

bool CanTouch(const Model& model, GeometryIndex ga, GeometryIndex gb) {
  const std::vector<GeometryInstance>& geos = model.geometries();
  if (model.mobilized_body(geos[ga].body) == model.mobilized_body(geos[gb].body)) return false;
  return !(std::holds_alternative<HalfSpace>(geos[ga].shape) &&
           std::holds_alternative<HalfSpace>(geos[gb].shape));
}

}  // namespace contact_internal

namespace {

using contact_internal::CanTouch;
using contact_internal::PairMatches;

std::string PairText(const std::string& a, const std::string& b) {
  return "[" + a + ", " + b + "]";
}

/// True when (a, b) matches two geometries that can touch.
bool MatchesAPossiblePair(const Model& model, const std::string& a, const std::string& b) {
  const GeometryIndex ng = static_cast<GeometryIndex>(model.geometries().size());
  for (GeometryIndex ga = 0; ga < ng; ++ga) {
    for (GeometryIndex gb = ga + 1; gb < ng; ++gb) {
      if (CanTouch(model, ga, gb) && PairMatches(model, a, b, ga, gb)) return true;
    }
  }
  return false;
}

/// The model's geometry names, at most 20 of them.
std::string GeometryNames(const Model& model) {
  const std::vector<GeometryInstance>& geos = model.geometries();
  if (geos.empty()) return "the model has none";
  constexpr std::size_t kMaxNames = 20;
  std::string out;
  for (std::size_t i = 0; i < geos.size() && i < kMaxNames; ++i) {
    if (i > 0) out += ", ";
    out += geos[i].name;
  }
  if (geos.size() > kMaxNames) out += ", ... (" + std::to_string(geos.size()) + " in all)";
  return out;
}

}  // namespace

std::string ContactNameProblem(const Model& model, const std::string& name) {
  if (name == "*") return "";
  for (const GeometryInstance& g : model.geometries()) {
    if (g.name == name) return "";
  }
  if (!model.HasBody(name)) {
    return "a geometry name (" + GeometryNames(model) + "), a body name, or '*'";
  }
  const BodyIndex body = model.GetBodyIndex(name);
  for (const GeometryInstance& g : model.geometries()) {
    if (g.body == body) return "";
  }
  return "a geometry name, the name of a body with collision geometry, or '*' (body '" + name +
         "' has no collision geometry: a body name stands for the geometry attached to that "
         "body, not to bodies welded to it, so it would match nothing)";
}

std::string CollisionGroupProblem(std::size_t num_names) {
  if (num_names >= 2) return "";
  return "a list of at least two names (pairs within a group are not evaluated; a group of " +
         std::string(num_names == 0 ? "no name" : "one name") + " leaves out nothing)";
}

std::string IncludedPairProblem(const Model& model, const std::string& a, const std::string& b) {
  if (MatchesAPossiblePair(model, a, b)) return "";
  return "a pair that can touch: " + PairText(a, b) +
         " matches no two geometries on different bodies (geometries on one body, or all on the "
         "world, never touch), so it would include nothing";
}

std::string ContactOverrideProblem(const Model& model, const std::vector<ContactPair>& pairs,
                                   const std::string& a, const std::string& b,
                                   const std::string& filters) {
  for (const ContactPair& p : pairs) {
    if (PairMatches(model, a, b, p.geometry_a, p.geometry_b)) return "";
  }
  const bool possible = MatchesAPossiblePair(model, a, b);
  return "a pair whose parameters it would change: " + PairText(a, b) +
         " matches no contact pair that is evaluated (" +
         (possible ? "every pair it matches is left out by " + filters +
                         " excluded_pairs, included_pairs or collision_groups, or joins two "
                         "bodies hinged to each other"
                   : std::string("it matches no two geometries on different bodies")) +
         ")";
}

}  // namespace idto
