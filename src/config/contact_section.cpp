// `scene.contact` (the contact law parameters, force tolerance, pair filters, per-pair
// overrides) and `mpc.contact` (the controller's own law parameters and per-pair overrides).

#include <string>
#include <utility>
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
    if (!group.IsSequence()) {
      reader_.FailValue(group, At(path, i), Describe(group), "a list of names");
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
    contact_.overrides.push_back(std::move(entry));
  }
}

std::string ConfigLoader::ContactName(const YAML::Node& node, const std::string& path) const {
  const std::string name = reader_.String(node, path);
  if (name == "*") return name;
  const Model& model = config_.model;
  if (model.HasBody(name)) return name;
  for (const GeometryInstance& g : model.geometries()) {
    if (g.name == name) return name;
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
