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
    // An entry that matches no two geometries that could touch would include nothing (the
    // check ContactEngine makes, here with the entry's key and line).
    for (std::size_t i = 0; i < options.included_pairs.size(); ++i) {
      const auto& [a, b] = options.included_pairs[i];
      const std::string expected = IncludedPairProblem(config_.model, a, b);
      if (!expected.empty()) {
        reader_.FailValue(c.Get("included_pairs")[i], At(c.Path("included_pairs"), i),
                          PairText(a, b), expected);
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
    if (!group.IsSequence()) {
      reader_.FailValue(group, At(path, i), Describe(group), "a list of names");
    }
    // A group of one name leaves out only pairs on one body, which never touch anyway.
    const std::string expected = CollisionGroupProblem(group.size());
    if (!expected.empty()) reader_.FailValue(group, At(path, i), Describe(group), expected);
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
    // An override that changes no evaluated pair would be lost (unless contact is off): the
    // check ContactEngine makes, here with the entry's key and line.
    const std::string expected = enable_contact_
                                     ? ContactOverrideProblem(config_.model, engine.pairs(),
                                                              entry.a, entry.b, "scene.contact's")
                                     : std::string();
    if (!expected.empty()) {
      reader_.FailValue(overrides[i], At(path, i), PairText(entry.a, entry.b), expected);
    }
    contact_.overrides.push_back(std::move(entry));
  }
}

std::string ConfigLoader::ContactName(const YAML::Node& node, const std::string& path) const {
  const std::string name = reader_.String(node, path);
  // The check ContactEngine makes, here with the entry's key and line.
  const std::string expected = ContactNameProblem(config_.model, name);
  if (!expected.empty()) reader_.FailValue(node, path, "'" + name + "'", expected);
  return name;
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
