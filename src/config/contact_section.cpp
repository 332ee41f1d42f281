// `scene.contact` (the contact law parameters, force tolerance, pair filters, per-pair
// overrides) and `mpc.contact` (the controller's own law parameters and per-pair overrides).

#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "config_loader.hpp"
#include "idto/core/errors.hpp"

namespace idto::config_internal {

namespace {

const std::vector<std::string> kContactParameterKeys = {
    "stiffness", "smoothing", "dissipation_velocity", "friction_coefficient", "stiction_velocity"};

std::vector<std::string> ContactKeys() {
  std::vector<std::string> keys = kContactParameterKeys;
  keys.insert(keys.end(), {"force_tolerance", "excluded_pairs", "included_pairs",
                           "collision_groups", "overrides"});
  return keys;
}

bool Matches(const Model& model, const std::string& name, GeometryIndex g) {
  const GeometryInstance& geo = model.geometries()[g];
  return name == "*" || name == geo.name || name == model.body_name(geo.body);
}

bool PairMatches(const Model& model, const std::string& a, const std::string& b, GeometryIndex ga,
                 GeometryIndex gb) {
  return (Matches(model, a, ga) && Matches(model, b, gb)) ||
         (Matches(model, a, gb) && Matches(model, b, ga));
}

/// True when (a, b) matches two geometries that could touch: on different rigid bodies, not two
/// half-spaces (the pairs ContactEngine considers before its filters).
bool MatchesAPossiblePair(const Model& model, const std::string& a, const std::string& b) {
  const std::vector<GeometryInstance>& geos = model.geometries();
  const GeometryIndex ng = static_cast<GeometryIndex>(geos.size());
  for (GeometryIndex ga = 0; ga < ng; ++ga) {
    for (GeometryIndex gb = ga + 1; gb < ng; ++gb) {
      if (model.mobilized_body(geos[ga].body) == model.mobilized_body(geos[gb].body)) continue;
      if (std::holds_alternative<HalfSpace>(geos[ga].shape) &&
          std::holds_alternative<HalfSpace>(geos[gb].shape)) {
        continue;
      }
      if (PairMatches(model, a, b, ga, gb)) return true;
    }
  }
  return false;
}

/// True when (a, b) matches a pair that `engine` evaluates.
bool MatchesAnEvaluatedPair(const Model& model, const ContactEngine& engine, const std::string& a,
                            const std::string& b) {
  for (const ContactPair& p : engine.pairs()) {
    if (PairMatches(model, a, b, p.geometry_a, p.geometry_b)) return true;
  }
  return false;
}

std::string PairText(const std::string& a, const std::string& b) {
  return "[" + a + ", " + b + "]";
}

/// The law's parameters present in `c`, over the values in *p.
void ReadContactParameters(const MapReader& c, ContactParameters* p) {
  p->stiffness = c.Positive("stiffness", p->stiffness);
  p->smoothing = c.Positive("smoothing", p->smoothing);
  p->dissipation_velocity = c.Positive("dissipation_velocity", p->dissipation_velocity);
  p->friction_coefficient = c.NonNegative("friction_coefficient", p->friction_coefficient);
  p->stiction_velocity = c.Positive("stiction_velocity", p->stiction_velocity);
}

}  // namespace

void ConfigLoader::LoadMpcContact(const YAML::Node& node, const std::string& path) {
  std::vector<std::string> keys = kContactParameterKeys;
  keys.push_back("overrides");
  const MapReader c(reader_, node, path, keys);
  ReadContactParameters(c, &contact_.parameters);
  // Appended after the scene's: overrides apply in order, so the controller's win.
  if (c.Has("overrides")) LoadContactOverrides(c.Get("overrides"), c.Path("overrides"));
}

void ConfigLoader::LoadContact(const YAML::Node& node, const std::string& path) {
  const MapReader c(reader_, node, path, ContactKeys());
  ContactOptions& options = contact_;
  ReadContactParameters(c, &options.parameters);
  options.force_tolerance = c.NonNegative("force_tolerance", options.force_tolerance);
  if (c.Has("excluded_pairs")) {
    options.excluded_pairs = ReadPairs(c.Get("excluded_pairs"), c.Path("excluded_pairs"));
  }
  if (c.Has("included_pairs")) {
    options.included_pairs = ReadPairs(c.Get("included_pairs"), c.Path("included_pairs"));
    // An entry that matches no two geometries that could touch would include nothing.
    for (std::size_t i = 0; i < options.included_pairs.size(); ++i) {
      const auto& [a, b] = options.included_pairs[i];
      if (!MatchesAPossiblePair(config_.model, a, b)) {
        reader_.Fail(c.Get("included_pairs")[i], At(c.Path("included_pairs"), i),
                     PairText(a, b) +
                         " matches no two geometries on different bodies (geometries on one "
                         "body, or all on the world, never touch); expected a pair that can touch");
      }
    }
  }
  if (c.Has("collision_groups")) {
    LoadContactGroups(c.Get("collision_groups"), c.Path("collision_groups"));
  }
  if (c.Has("overrides")) LoadContactOverrides(c.Get("overrides"), c.Path("overrides"));
}

void ConfigLoader::LoadContactGroups(const YAML::Node& groups, const std::string& path) {
  if (!groups.IsSequence()) {
    reader_.FailValue(groups, path, Describe(groups), "a list of lists of names");
  }
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const YAML::Node group = groups[i];
    if (!group.IsSequence() || group.size() < 2) {
      // A group of one name leaves out only pairs on one body, which never touch anyway.
      reader_.FailValue(group, At(path, i), Describe(group),
                        "a list of at least two names (pairs within a group are not evaluated)");
    }
    std::vector<std::string> names;
    for (std::size_t j = 0; j < group.size(); ++j) {
      names.push_back(ContactName(group[j], At(At(path, i), j)));
    }
    contact_.collision_groups.push_back(std::move(names));
  }
}

void ConfigLoader::LoadContactOverrides(const YAML::Node& overrides, const std::string& path) {
  if (!overrides.IsSequence()) {
    reader_.FailValue(overrides, path, Describe(overrides),
                      "a list of {a, b, <contact parameter>: value}");
  }
  std::vector<std::string> keys = {"a", "b"};
  keys.insert(keys.end(), kContactParameterKeys.begin(), kContactParameterKeys.end());
  // The pairs evaluated under the filters read so far (the scene's: they come before the
  // overrides in scene.contact, and mpc.contact has none of its own).
  ContactOptions filters = contact_;
  filters.overrides.clear();
  const ContactEngine engine(config_.model, filters);
  for (std::size_t i = 0; i < overrides.size(); ++i) {
    const MapReader o(reader_, overrides[i], At(path, i), keys);
    ContactParameterOverride entry;
    entry.a = ContactName(o.Require("a"), o.Path("a"));
    entry.b = ContactName(o.Require("b"), o.Path("b"));
    if (o.Has("stiffness")) entry.stiffness = o.Positive("stiffness", 0.0);
    if (o.Has("smoothing")) entry.smoothing = o.Positive("smoothing", 0.0);
    if (o.Has("dissipation_velocity")) {
      entry.dissipation_velocity = o.Positive("dissipation_velocity", 0.0);
    }
    if (o.Has("friction_coefficient")) {
      entry.friction_coefficient = o.NonNegative("friction_coefficient", 0.0);
    }
    if (o.Has("stiction_velocity")) {
      entry.stiction_velocity = o.Positive("stiction_velocity", 0.0);
    }
    // An override that changes no evaluated pair would be lost (unless contact is off).
    if (enable_contact_ && !MatchesAnEvaluatedPair(config_.model, engine, entry.a, entry.b)) {
      const bool possible = MatchesAPossiblePair(config_.model, entry.a, entry.b);
      reader_.Fail(overrides[i], At(path, i),
                   PairText(entry.a, entry.b) + " matches no contact pair that is evaluated (" +
                       (possible ? "every pair it matches is left out by scene.contact's "
                                   "excluded_pairs, included_pairs or collision_groups, or joins "
                                   "two bodies hinged to each other"
                                 : "it matches no two geometries on different bodies") +
                       "); expected a pair whose parameters it would change");
    }
    contact_.overrides.push_back(std::move(entry));
  }
}

std::string ConfigLoader::ContactName(const YAML::Node& node, const std::string& path) const {
  const std::string name = reader_.String(node, path);
  if (name == "*") return name;
  const Model& model = config_.model;
  for (const GeometryInstance& g : model.geometries()) {
    if (g.name == name) return name;
  }
  if (model.HasBody(name)) {
    // A body name stands for the geometry attached to that body, not to the bodies welded to it.
    const BodyIndex body = model.GetBodyIndex(name);
    for (const GeometryInstance& g : model.geometries()) {
      if (g.body == body) return name;
    }
    reader_.Fail(node, path,
                 "body '" + name +
                     "' has no collision geometry (a body name stands for the geometry "
                     "attached to that body, not to bodies welded to it), so it would match "
                     "nothing; expected a geometry name, a body with geometry, or '*'");
  }
  std::vector<std::string> geometry_names;
  for (const GeometryInstance& g : model.geometries()) geometry_names.push_back(g.name);
  reader_.FailValue(node, path, "'" + name + "'",
                    "a geometry name (" +
                        (geometry_names.empty() ? std::string("the scene has none")
                                                : JoinNames(geometry_names, 20)) +
                        "), a body name, or '*'");
}

std::vector<std::pair<std::string, std::string>> ConfigLoader::ReadPairs(
    const YAML::Node& node, const std::string& path) const {
  if (!node.IsSequence()) {
    reader_.FailValue(node, path, Describe(node), "a list of name pairs [a, b]");
  }
  std::vector<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node pair = node[i];
    if (!pair.IsSequence() || pair.size() != 2) {
      reader_.FailValue(pair, At(path, i), Describe(pair), "a pair of names [a, b]");
    }
    pairs.emplace_back(ContactName(pair[0], At(At(path, i), 0)),
                       ContactName(pair[1], At(At(path, i), 1)));
  }
  return pairs;
}

}  // namespace idto::config_internal
