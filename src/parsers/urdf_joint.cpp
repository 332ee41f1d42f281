// URDF <joint>: type, links, <origin>, <axis>, <dynamics> and <limit>, read with TinyXML.

#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <tinyxml.h>

#include "idto/core/errors.hpp"
#include "urdf_document.hpp"

namespace idto {
namespace urdf_internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

const std::map<std::string, JointType>& JointTypes() {
  static const std::map<std::string, JointType> kTypes = {
      {"revolute", JointType::kRevolute},   {"continuous", JointType::kContinuous},
      {"prismatic", JointType::kPrismatic}, {"fixed", JointType::kFixed},
      {"floating", JointType::kFloating},   {"planar", JointType::kPlanar}};
  return kTypes;
}

std::string LinkOf(const TiXmlElement& e, const char* tag, const std::string& element,
                   const UrdfReporter& reporter) {
  const TiXmlElement* link = e.FirstChildElement(tag);
  if (link == nullptr) return "";
  CheckValueElement(*link, {"link"}, element, reporter);
  if (link->Attribute("link") == nullptr) return "";
  return link->Attribute("link");
}

/// Checks the children of <joint>: used, ignored with a warning, or refused.
void CheckJointChildren(const TiXmlElement& e, const std::string& element, UrdfReporter* reporter) {
  for (const TiXmlElement* c = e.FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    const std::string tag = c->Value();
    const std::string line = " (line " + std::to_string(c->Row()) + ")";
    if (tag == "origin" || tag == "parent" || tag == "child" || tag == "axis" || tag == "limit" ||
        tag == "dynamics") {
      if (c->NextSiblingElement(tag.c_str()) != nullptr) {
        reporter->Error(element, "several " + Tag(*c) + " elements" + line + "; expected one");
      }
    } else if (tag == "safety_controller" || tag == "calibration") {
      reporter->Warn(element, Tag(*c) + line + " ignored (not used by idto)");
    } else if (tag == "mimic") {
      reporter->Error(element, "<mimic>" + line +
                                   " is not supported: idto would move the joint independently; "
                                   "model the coupling in the problem instead");
    } else {
      reporter->Error(element, "unsupported element " + Tag(*c) + line);
    }
  }
}

/// An effort or velocity limit: absent or 0 = none; otherwise positive.
double ReadRate(const TiXmlElement& limit, const char* attribute, const std::string& element,
                const UrdfReporter& reporter) {
  const double value = ReadNumber(limit, attribute, 0.0, element, reporter);
  if (std::isnan(value) || value < 0.0) {
    reporter.Error(element, "<limit " + std::string(attribute) + "> is " + FormatValue(value) +
                                "; expected a non-negative number (0 = no limit)");
  }
  return value > 0.0 ? value : kInf;
}

/// Reads <limit>. On a fixed joint the numbers are checked and have no effect (nothing moves).
void ReadLimits(const TiXmlElement& limit, const std::string& element, UrdfReporter* reporter,
                JointSpec* spec) {
  CheckValueElement(limit, {"lower", "upper", "effort", "velocity"}, element, *reporter);
  const bool fixed = spec->type == JointType::kFixed;
  const double effort = ReadRate(limit, "effort", element, *reporter);
  const double velocity = ReadRate(limit, "velocity", element, *reporter);
  const bool has_position = limit.Attribute("lower") != nullptr || limit.Attribute("upper");
  const double lower = ReadNumber(limit, "lower", -kInf, element, *reporter);
  const double upper = ReadNumber(limit, "upper", kInf, element, *reporter);
  if (std::isnan(lower) || std::isnan(upper) || lower > upper) {
    reporter->Error(element, "<limit> lower = " + FormatValue(lower) + " and upper = " +
                                 FormatValue(upper) + "; expected lower <= upper");
  }
  if (fixed) return;
  spec->effort_limit = effort;
  spec->velocity_limit = velocity;
  if (spec->type == JointType::kRevolute || spec->type == JointType::kPrismatic) {
    spec->lower_limit = lower;
    spec->upper_limit = upper;
  } else if (has_position) {
    reporter->Warn(element, "<limit lower/upper> ignored: the joint's coordinates are unbounded");
  }
}

}  // namespace

UrdfJoint ReadJoint(const TiXmlElement& e, UrdfReporter* reporter) {
  UrdfJoint joint;
  joint.line = e.Row();
  if (const char* name = e.Attribute("name")) joint.name = name;
  if (joint.name.empty()) {
    reporter->Error("joint (line " + std::to_string(joint.line) + ")",
                    "the <joint> has no name attribute");
  }
  const std::string element = JointElement(joint.name);
  if (const char* type = e.Attribute("type")) joint.type = type;
  const auto type = JointTypes().find(joint.type);
  if (type == JointTypes().end()) {
    reporter->Error(element,
                    "unknown joint type '" + joint.type +
                        "'; expected revolute, continuous, prismatic, fixed, floating or planar");
  }
  CheckStructuralElement(e, {"name", "type"}, element, reporter);
  joint.parent = LinkOf(e, "parent", element, *reporter);
  joint.child = LinkOf(e, "child", element, *reporter);
  if (joint.parent.empty()) reporter->Error(element, "no <parent link=\"...\"/> given");
  if (joint.child.empty()) reporter->Error(element, "no <child link=\"...\"/> given");
  if (joint.parent == joint.child) {
    reporter->Error(element, "connects link '" + joint.child + "' to itself");
  }
  CheckJointChildren(e, element, reporter);

  JointSpec& spec = joint.spec;
  spec.name = joint.name;
  spec.type = type->second;
  spec.X_PJ = ReadOrigin(e, element, "joint", *reporter);
  const bool has_axis = spec.type == JointType::kRevolute || spec.type == JointType::kContinuous ||
                        spec.type == JointType::kPrismatic || spec.type == JointType::kPlanar;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // the URDF default
  if (const TiXmlElement* a = e.FirstChildElement("axis")) {
    // Checked on every joint; a fixed or floating joint has no axis, so there it has no effect.
    CheckValueElement(*a, {"xyz"}, element, *reporter);
    axis = ReadVector3(*a, "xyz", axis, element, *reporter);
  }
  if (has_axis) {
    const double norm = axis.norm();
    if (!std::isfinite(norm) || norm <= 1e-12) {
      reporter->Error(
          element, "<axis xyz> is " + FormatVector(axis) + "; expected a non-zero finite vector");
    }
    spec.axis = axis / norm;
  }
  if (const TiXmlElement* d = e.FirstChildElement("dynamics")) {
    CheckValueElement(*d, {"damping", "friction"}, element, *reporter);
    const double damping = ReadNumber(*d, "damping", 0.0, element, *reporter);
    if (!std::isfinite(damping) || damping < 0.0) {
      reporter->Error(element, "<dynamics damping> is " + FormatValue(damping) +
                                   "; expected a non-negative number");
    }
    if (spec.type != JointType::kFixed) spec.damping = damping;
    const double friction = ReadNumber(*d, "friction", 0.0, element, *reporter);
    if (friction != 0.0 && spec.type != JointType::kFixed) {
      reporter->Warn(element, "<dynamics friction> = " + FormatValue(friction) +
                                  " ignored (idto models viscous damping only)");
    }
  }
  if (const TiXmlElement* limit = e.FirstChildElement("limit")) {
    ReadLimits(*limit, element, reporter, &spec);
  }
  return joint;
}

}  // namespace urdf_internal
}  // namespace idto
