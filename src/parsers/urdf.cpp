#include "idto/parsers/urdf.hpp"

// URDF -> Model.
//
// The document is read with TinyXML (urdf_document.cpp, urdf_link.cpp, urdf_joint.cpp), after a
// linear scan bounds its nesting depth: every element is either used or reported, numbers are
// parsed strictly. urdfdom then reads the same text as a cross-check (urdf_urdfdom.cpp): when it
// accepts the file, it must not find more links, joints or collision shapes than idto kept.
// This file turns the document into bodies, joints, frames and geometry of a ModelBuilder.
//
// Conventions (see include/idto/parsers/urdf.hpp, docs/urdf.md and models/README.md):
//  - one body per URDF link, added in depth-first order from the root, the children of a link in
//    the document order of their joints; the body frame of a link is its URDF link frame (the
//    joint frame of its parent joint at q = 0);
//  - a root link named "world" (declared, or implicit: only named as a joint's parent) stands
//    for the world: its child joints attach to the world body at options.X_WB, its collision
//    geometry goes to the world; options.base is then not used;
//  - boxes are replaced by their inscribed spheres when options.box_inscribed_spheres is set.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "urdf_document.hpp"

namespace idto {
namespace {

using urdf_internal::FormatVector;
using urdf_internal::JointElement;
using urdf_internal::LinkElement;
using urdf_internal::UrdfDocument;
using urdf_internal::UrdfJoint;
using urdf_internal::UrdfLink;
using urdf_internal::UrdfReporter;

bool IsFinite(const Eigen::Isometry3d& X) { return X.matrix().allFinite(); }

std::string ReadFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) ThrowFileError(path, "", "file not found");
  if (!std::filesystem::is_regular_file(path, error)) {
    ThrowFileError(path, "", "not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowFileError(path, "", "cannot open the file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) ThrowFileError(path, "", "error while reading the file");
  return text.str();
}

/// Checks the options that do not depend on the document.
void CheckOptions(const UrdfOptions& options, const std::vector<UrdfWarning>* warnings,
                  const char* where) {
  if (!IsFinite(options.X_WB)) {
    ThrowInvalidArgument(where, "options.X_WB", "not finite", "a finite pose");
  }
  if (options.box_inscribed_spheres.has_value()) {
    const InscribedSpheresOptions& spheres = *options.box_inscribed_spheres;
    if (spheres.num_per_axis < 2 || spheres.num_per_axis > 100) {
      ThrowInvalidArgument(where, "options.box_inscribed_spheres->num_per_axis",
                           std::to_string(spheres.num_per_axis), "an integer from 2 to 100");
    }
    if (!(spheres.radius_fraction > 0.0 && spheres.radius_fraction <= 0.5)) {
      ThrowInvalidArgument(where, "options.box_inscribed_spheres->radius_fraction",
                           FormatValue(spheres.radius_fraction), "a number in (0, 0.5]");
    }
  }
  if (options.base != BaseType::kPlanar && options.planar_normal != Eigen::Vector3d::UnitZ()) {
    // Only a planar base has a plane: the normal would be dropped.
    ThrowInvalidArgument(where, "options.planar_normal", FormatVector(options.planar_normal),
                         "the default (0, 0, 1) unless options.base is BaseType::kPlanar");
  }
  if (options.unsupported_visuals_as_warnings && warnings == nullptr) {
    ThrowInvalidArgument(where, "warnings", "null with options.unsupported_visuals_as_warnings",
                         "a vector to collect the warnings in (they would be lost otherwise)");
  }
}

/// The document, read and checked, with its options.
struct ParsedUrdf {
  UrdfDocument doc;
  std::string source;
};

ParsedUrdf Parse(const std::string& xml, const std::string& source, const UrdfOptions& options,
                 std::vector<UrdfWarning>* warnings, const char* where) {
  CheckOptions(options, warnings, where);
  UrdfReporter reporter(source, options.unsupported_visuals_as_warnings, options.prefix, warnings);
  ParsedUrdf parsed;
  parsed.source = source;
  parsed.doc = urdf_internal::ReadUrdfDocument(xml, &reporter);
  urdf_internal::CrossCheckWithUrdfdom(xml, parsed.doc, reporter);
  return parsed;
}

/// Depth-first order from the root, children in the document order of their joints.
std::vector<std::string> DepthFirstOrder(const UrdfDocument& doc) {
  std::vector<std::string> order;
  std::vector<std::string> stack = {doc.root};
  while (!stack.empty()) {
    const std::string link = stack.back();
    stack.pop_back();
    order.push_back(link);
    const auto it = doc.child_joints.find(link);
    if (it == doc.child_joints.end()) continue;
    for (auto j = it->second.rbegin(); j != it->second.rend(); ++j) {
      stack.push_back(doc.joints[static_cast<size_t>(*j)].child);
    }
  }
  return order;
}

const UrdfJoint& ParentJoint(const UrdfDocument& doc, const std::string& link) {
  return doc.joints[static_cast<size_t>(doc.parent_joint.at(link))];
}

/// Mass checks that name the link: mass welded to the world is ignored (a warning); a moving
/// link that carries no mass at all (itself, welded or moving below it) is an error. Whether
/// the joint-space mass matrix is positive definite is left to ModelBuilder::Build().
void CheckMasses(const UrdfDocument& doc, const std::vector<std::string>& order,
                 const UrdfOptions& options, UrdfReporter* reporter) {
  const bool world_root = doc.root == "world";
  std::map<std::string, bool> welded_to_world;
  std::map<std::string, double> carried;  // mass of the link and everything below it
  for (const std::string& name : order) {
    bool welded = world_root || options.base == BaseType::kFixed;
    if (name != doc.root) {
      const UrdfJoint& joint = ParentJoint(doc, name);
      welded = welded_to_world.at(joint.parent) && joint.spec.type == JointType::kFixed;
    }
    welded_to_world[name] = welded;
    const double mass = doc.link(name).inertia.mass;
    if (welded && mass > 0.0) {
      reporter->Warn(LinkElement(name),
                     "mass " + FormatValue(mass) + " ignored: the link is " +
                         (name == "world" && world_root ? "the world" : "welded to the world") +
                         " and does not move");
    }
  }
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    carried[*it] += doc.link(*it).inertia.mass;
    if (*it != doc.root) carried[ParentJoint(doc, *it).parent] += carried[*it];
  }
  for (const std::string& name : order) {
    if (welded_to_world.at(name) || carried.at(name) > 0.0) continue;
    if (name != doc.root && ParentJoint(doc, name).spec.type == JointType::kFixed) continue;
    std::string problem;
    if (name == doc.root) {
      problem = std::string("the link is the ") +
                (options.base == BaseType::kFloating ? "floating" : "planar") + " base but ";
    } else {
      const UrdfJoint& joint = ParentJoint(doc, name);
      problem = "the link moves (" + joint.type + " joint '" + joint.name + "') but ";
    }
    const UrdfLink& link = doc.link(name);
    problem += link.has_inertial ? "its mass is " + FormatValue(link.inertia.mass)
                                 : std::string("has no <inertial>");
    reporter->Error(LinkElement(name),
                    problem +
                        " and nothing it carries has mass; a moving link needs a positive "
                        "mass (its own or that of the links it carries)");
  }
}

/// Geometry names unique within one call (a repeated <collision name> gets "_1", "_2", ...,
/// with a warning: contact filters naming it would otherwise silently miss the renamed ones).
std::string UniqueName(const std::string& name, const std::string& link,
                       std::set<std::string>* used, UrdfReporter* reporter) {
  std::string candidate = name;
  for (int k = 1; used->count(candidate) > 0; ++k) candidate = name + "_" + std::to_string(k);
  used->insert(candidate);
  if (candidate != name) {
    reporter->Warn(LinkElement(link), "collision name '" + name +
                                          "' is already used in this model; this one is named '" +
                                          candidate + "'");
  }
  return candidate;
}

struct PlannedGeometry {
  std::string name;       // prefixed, unique
  std::string urdf_name;  // as in the file (or the default name)
  Eigen::Isometry3d X_LG;
  Shape shape;
};

/// Collision geometry of every link, named (and boxes replaced by spheres when asked).
std::map<std::string, std::vector<PlannedGeometry>> PlanGeometry(
    const UrdfDocument& doc, const std::vector<std::string>& order, const UrdfOptions& options,
    UrdfReporter* reporter) {
  std::map<std::string, std::vector<PlannedGeometry>> geometry_of;
  std::set<std::string> names;
  for (const std::string& link : order) {
    for (const urdf_internal::UrdfCollision& c : doc.link(link).collisions) {
      PlannedGeometry g{UniqueName(options.prefix + c.name, link, &names, reporter), c.name, c.X_LG,
                        c.shape};
      const Box* box = std::get_if<Box>(&c.shape);
      if (box == nullptr || !options.box_inscribed_spheres.has_value()) {
        geometry_of[link].push_back(g);
        continue;
      }
      // The box's inscribed spheres instead of the box, named after the box's (unique) name.
      const std::vector<InscribedSphere> spheres =
          InscribedSpheres(*box, *options.box_inscribed_spheres);
      for (std::size_t k = 0; k < spheres.size(); ++k) {
        const std::string suffix = "_sphere" + std::to_string(k);
        geometry_of[link].push_back(PlannedGeometry{
            UniqueName(g.name + suffix, link, &names, reporter), g.urdf_name + suffix,
            g.X_LG * spheres[k].X_BoxSphere, spheres[k].sphere});
      }
    }
  }
  return geometry_of;
}

[[noreturn]] void RethrowFromBuilder(const std::string& source, const std::string& element,
                                     const std::exception& e) {
  ThrowFileError(source, element, std::string("rejected by ModelBuilder: ") + e.what());
}

/// The joint that attaches the root link (not "world") to the world.
JointSpec RootJoint(const std::string& root, const UrdfOptions& options) {
  JointSpec joint;
  joint.name = root + "_root_joint";
  joint.X_PJ = options.X_WB;
  switch (options.base) {
    case BaseType::kFixed:
      joint.type = JointType::kFixed;
      break;
    case BaseType::kFloating:
      joint.type = JointType::kFloating;
      break;
    case BaseType::kPlanar:
      joint.type = JointType::kPlanar;
      joint.axis = options.planar_normal.normalized();
      break;
  }
  return joint;
}

/// Adds the bodies, frames and geometry. Only the builder's own checks (e.g. names already used
/// by another model) can fail here; the builder then holds the bodies added so far.
BodyIndex AddBodies(const ParsedUrdf& parsed, const std::vector<std::string>& order,
                    const std::map<std::string, std::vector<PlannedGeometry>>& geometry_of,
                    const UrdfOptions& options, ModelBuilder* builder) {
  const UrdfDocument& doc = parsed.doc;
  const std::string& source = parsed.source;
  const std::string& prefix = options.prefix;
  std::map<std::string, BodyIndex> body_of;
  auto add_geometry = [&](const std::string& link, BodyIndex body, const Eigen::Isometry3d& X_BL) {
    const auto it = geometry_of.find(link);
    if (it == geometry_of.end()) return;
    for (const PlannedGeometry& g : it->second) {
      try {
        builder->AddGeometry(g.name, body, X_BL * g.X_LG, g.shape);
      } catch (const std::invalid_argument& e) {
        RethrowFromBuilder(source, LinkElement(link) + " (collision '" + g.urdf_name + "')", e);
      }
    }
  };
  BodyIndex root_body = kWorldBody;
  for (const std::string& name : order) {
    const std::string element = LinkElement(name);
    if (name == doc.root && name == "world") {
      body_of[name] = kWorldBody;
      if (!prefix.empty()) {
        try {
          builder->AddFrame(prefix + name, kWorldBody, options.X_WB);
        } catch (const std::invalid_argument& e) {
          RethrowFromBuilder(source, element, e);
        }
      }
      add_geometry(name, kWorldBody, options.X_WB);
      continue;
    }
    JointSpec joint = RootJoint(name, options);
    BodyIndex parent = kWorldBody;
    if (name != doc.root) {
      const UrdfJoint& urdf_joint = ParentJoint(doc, name);
      joint = urdf_joint.spec;
      parent = body_of.at(urdf_joint.parent);
      if (parent == kWorldBody) joint.X_PJ = options.X_WB * joint.X_PJ;
    }
    joint.name = prefix + joint.name;
    BodyIndex body = kWorldBody;
    try {
      body = builder->AddBody(prefix + name, doc.link(name).inertia, parent, joint);
    } catch (const std::invalid_argument& e) {
      RethrowFromBuilder(source, element + " (joint '" + joint.name + "')", e);
    }
    body_of[name] = body;
    if (name == doc.root) root_body = body;
    add_geometry(name, body, Eigen::Isometry3d::Identity());
  }
  return root_body;
}

BodyIndex AddParsed(const ParsedUrdf& parsed, const UrdfOptions& options, ModelBuilder* builder,
                    const char* where, std::vector<UrdfWarning>* warnings) {
  const UrdfDocument& doc = parsed.doc;
  if (doc.root != "world" && options.base == BaseType::kPlanar) {
    const double n = options.planar_normal.norm();
    if (!std::isfinite(n) || n <= 1e-12) {
      ThrowInvalidArgument(where, "options.planar_normal", FormatVector(options.planar_normal),
                           "a non-zero finite vector");
    }
  }
  UrdfReporter reporter(parsed.source, options.unsupported_visuals_as_warnings, options.prefix,
                        warnings);
  if (doc.root == "world" && options.base != BaseType::kFixed) {
    // The file attaches the model to the world itself: a floating or planar base asked for in
    // the options could not apply, and would otherwise be dropped without a word.
    reporter.Error("robot '" + doc.robot_name + "'",
                   std::string("the root link is 'world' (the file attaches the model to the "
                               "world), but options.base (a scene model's `base`) is ") +
                       (options.base == BaseType::kFloating ? "floating" : "planar") +
                       "; expected fixed (the default) for such a file");
  }
  const std::vector<std::string> order = DepthFirstOrder(doc);
  CheckMasses(doc, order, options, &reporter);
  const auto geometry_of = PlanGeometry(doc, order, options, &reporter);
  return AddBodies(parsed, order, geometry_of, options, builder);
}

/// Builds, naming the link or joint a builder error is about when its (prefixed) name appears
/// in the message.
Model BuildModel(const ModelBuilder& builder, const ParsedUrdf& parsed, const std::string& prefix) {
  try {
    return builder.Build();
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    std::string element = "robot '" + parsed.doc.robot_name + "'";
    size_t best = 0;
    auto consider = [&](const std::string& name, const std::string& candidate) {
      const std::string quoted = "\"" + prefix + name + "\"";
      if (quoted.size() > best && message.find(quoted) != std::string::npos) {
        best = quoted.size();
        element = candidate;
      }
    };
    for (const UrdfLink& link : parsed.doc.links) consider(link.name, LinkElement(link.name));
    for (const UrdfJoint& joint : parsed.doc.joints) {
      consider(joint.name, JointElement(joint.name));
    }
    RethrowFromBuilder(parsed.source, element, e);
  }
}

Model ParseAndBuild(const std::string& xml, const UrdfOptions& options, const std::string& source,
                    const char* where, std::vector<UrdfWarning>* warnings) {
  const ParsedUrdf parsed = Parse(xml, source, options, warnings, where);
  ModelBuilder builder(options.model_name.empty() ? parsed.doc.robot_name : options.model_name);
  AddParsed(parsed, options, &builder, where, warnings);
  return BuildModel(builder, parsed, options.prefix);
}

}  // namespace

Model ParseUrdfFile(const std::string& path, const UrdfOptions& options,
                    std::vector<UrdfWarning>* warnings) {
  return ParseAndBuild(ReadFile(path), options, path, "ParseUrdfFile", warnings);
}

Model ParseUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                      const std::string& source_name, std::vector<UrdfWarning>* warnings) {
  return ParseAndBuild(urdf_xml, options, source_name, "ParseUrdfString", warnings);
}

BodyIndex AddUrdfFile(const std::string& path, const UrdfOptions& options, ModelBuilder* builder,
                      std::vector<UrdfWarning>* warnings) {
  if (builder == nullptr) ThrowInvalidArgument("AddUrdfFile", "builder", "null", "a ModelBuilder");
  const ParsedUrdf parsed = Parse(ReadFile(path), path, options, warnings, "AddUrdfFile");
  return AddParsed(parsed, options, builder, "AddUrdfFile", warnings);
}

BodyIndex AddUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                        ModelBuilder* builder, const std::string& source_name,
                        std::vector<UrdfWarning>* warnings) {
  if (builder == nullptr) {
    ThrowInvalidArgument("AddUrdfString", "builder", "null", "a ModelBuilder");
  }
  const ParsedUrdf parsed = Parse(urdf_xml, source_name, options, warnings, "AddUrdfString");
  return AddParsed(parsed, options, builder, "AddUrdfString", warnings);
}

}  // namespace idto
