// URDF <link>: <inertial>, <collision> and <visual>, read with TinyXML so that every element is
// either used or reported (urdfdom stops reading a link at the first element it cannot parse).

#include <algorithm>
#include <cmath>
#include <string>

#include <tinyxml.h>
#include <Eigen/Eigenvalues>

#include "idto/core/errors.hpp"
#include "urdf_document.hpp"

namespace idto {
namespace urdf_internal {
namespace {

constexpr const char* kShapes = "<sphere>, <box>, <cylinder>, <capsule> or <drake:capsule>";

/// "collision 'name' (line N)".
std::string Describe(const char* kind, const std::string& name, const TiXmlElement& e) {
  return std::string(kind) + " " + Quoted(name) + " (line " + std::to_string(e.Row()) + ")";
}

/// Checks the mass properties of one <inertial> on their own.
void CheckInertial(double mass, const Eigen::Matrix3d& I, const std::string& element,
                   const UrdfReporter& reporter) {
  if (!std::isfinite(mass) || mass < 0.0) {
    reporter.Error(element, "<inertial> mass is " + FormatValue(mass) +
                                "; expected a finite non-negative number");
  }
  if (!I.allFinite()) {
    reporter.Error(element, "<inertia> has a non-finite entry: diagonal " +
                                FormatVector(I.diagonal()) + ", off-diagonal " +
                                FormatVector(Eigen::Vector3d(I(0, 1), I(0, 2), I(1, 2))));
  }
  const Eigen::Vector3d e =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  const double tol = 1e-9 * std::max(e.cwiseAbs().maxCoeff(), 1e-300);
  if (e(0) < -tol) {
    reporter.Error(element, "<inertia> is not positive semi-definite: principal moments " +
                                FormatVector(e) + "; expected all >= 0");
  }
  if (e(0) + e(1) < e(2) - tol) {
    reporter.Error(element, "<inertia> violates the triangle inequality: principal moments " +
                                FormatVector(e) +
                                "; expected the two smallest to sum to at least the largest");
  }
}

/// Reads <inertial>: mass properties in the link frame.
BodyInertia ReadInertial(const TiXmlElement& e, const std::string& element,
                         UrdfReporter* reporter) {
  for (const TiXmlElement* c = e.FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    const std::string tag = c->Value();
    if (tag != "origin" && tag != "mass" && tag != "inertia") {
      reporter->Error(element, "<inertial> has an unsupported element " + Tag(*c) + " (line " +
                                   std::to_string(c->Row()) +
                                   "); expected <origin>, <mass> and <inertia>");
    }
  }
  CheckStructuralElement(e, {}, element, reporter);
  const TiXmlElement* mass_xml = e.FirstChildElement("mass");
  const TiXmlElement* inertia_xml = e.FirstChildElement("inertia");
  if (mass_xml == nullptr) {
    reporter->Error(
        element, "<inertial> (line " + std::to_string(e.Row()) + ") has no <mass value=\"...\"/>");
  }
  if (inertia_xml == nullptr) {
    reporter->Error(element, "<inertial> (line " + std::to_string(e.Row()) +
                                 ") has no <inertia .../> (write zeros for a point mass)");
  }
  for (const TiXmlElement* first : {mass_xml, inertia_xml}) {
    if (const TiXmlElement* second = first->NextSiblingElement(first->Value())) {
      reporter->Error(element, "<inertial> (line " + std::to_string(e.Row()) + ") has several " +
                                   Tag(*first) + " elements (lines " +
                                   std::to_string(first->Row()) + " and " +
                                   std::to_string(second->Row()) + "); expected one");
    }
  }
  CheckValueElement(*mass_xml, {"value"}, element, *reporter);
  CheckValueElement(*inertia_xml, {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}, element, *reporter);
  const double mass = ReadRequiredNumber(*mass_xml, "value", element, *reporter);
  auto entry = [&](const char* name) {
    return ReadRequiredNumber(*inertia_xml, name, element, *reporter);
  };
  const double ixx = entry("ixx"), ixy = entry("ixy"), ixz = entry("ixz");
  const double iyy = entry("iyy"), iyz = entry("iyz"), izz = entry("izz");
  Eigen::Matrix3d I;
  I << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
  CheckInertial(mass, I, element, *reporter);
  const Eigen::Isometry3d X_LI = ReadOrigin(e, element, "<inertial>", *reporter);
  BodyInertia inertia;
  inertia.mass = mass;
  inertia.p_BBcm = X_LI.translation();
  const Eigen::Matrix3d R = X_LI.linear();
  inertia.I_BBcm_B = R * I * R.transpose();
  inertia.I_BBcm_B = 0.5 * (inertia.I_BBcm_B + inertia.I_BBcm_B.transpose());
  return inertia;
}

/// Reads the one shape inside <geometry>. Returns false (after reporting it) when idto does not
/// support the shape; throws on malformed numbers, and on non-physical sizes when `check_sizes`.
bool ReadShape(const TiXmlElement& geometry, const std::string& element, const std::string& what,
               bool visual, UrdfReporter* reporter, Shape* shape) {
  const TiXmlElement* s = geometry.FirstChildElement();
  if (s == nullptr) reporter->Error(element, what + ": <geometry> is empty; expected " + kShapes);
  if (s->NextSiblingElement() != nullptr) {
    reporter->Error(element, what + ": <geometry> holds " + Tag(*s) + " and " +
                                 Tag(*s->NextSiblingElement()) + "; expected exactly one shape");
  }
  const std::string tag = s->Value();
  if (tag == "sphere") {
    CheckValueElement(*s, {"radius"}, element, *reporter);
  } else if (tag == "box") {
    CheckValueElement(*s, {"size"}, element, *reporter);
  } else if (tag == "cylinder" || tag == "capsule" || tag == "drake:capsule") {
    CheckValueElement(*s, {"radius", "length"}, element, *reporter);
  }
  auto size = [&](const char* attribute) {
    const double value = ReadRequiredNumber(*s, attribute, element, *reporter);
    const bool zero_ok = std::string(attribute) == "length" && tag != "cylinder";
    if (!visual && !(std::isfinite(value) && (value > 0.0 || (zero_ok && value == 0.0)))) {
      reporter->Error(element, what + ": <" + tag + " " + attribute + "> is " + FormatValue(value) +
                                   "; expected a finite positive number");
    }
    return value;
  };
  if (tag == "sphere") {
    *shape = Sphere{size("radius")};
  } else if (tag == "cylinder") {
    const double radius = size("radius");
    *shape = Cylinder{radius, size("length")};
  } else if (tag == "capsule" || tag == "drake:capsule") {
    const double radius = size("radius");
    *shape = Capsule{radius, size("length")};
  } else if (tag == "box") {
    Box box;
    box.size = ReadVector3(*s, "size", Eigen::Vector3d::Constant(-1.0), element, *reporter);
    for (int i = 0; i < 3 && !visual; ++i) {
      if (!(std::isfinite(box.size(i)) && box.size(i) > 0.0)) {
        reporter->Error(element, what + ": <box size> is " + FormatVector(box.size) +
                                     "; expected three finite positive numbers");
      }
    }
    *shape = box;
  } else {
    std::string found = Tag(*s);
    if (const char* file = s->Attribute("filename")) {
      found = "<" + tag + " filename=\"" + file + "\">";
    }
    reporter->Unsupported(element,
                          what + ": " + found + " is not supported (idto's contact geometry is " +
                              kShapes + "); replace it by primitive shapes",
                          visual);
    return false;
  }
  return true;
}

/// Reads one <collision>. Returns false when it holds no supported shape (reported).
bool ReadCollision(const TiXmlElement& e, const std::string& link, int position,
                   UrdfReporter* reporter, UrdfCollision* collision) {
  const std::string element = LinkElement(link);
  const char* name = e.Attribute("name");
  collision->name = (name != nullptr && *name != '\0')
                        ? std::string(name)
                        : link + "_collision_" + std::to_string(position);
  const std::string what = Describe("collision", collision->name, e);
  CheckStructuralElement(e, {"name"}, element, reporter);
  const TiXmlElement* geometry = e.FirstChildElement("geometry");
  for (const TiXmlElement* c = e.FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    const std::string tag = c->Value();
    if (tag == "geometry" && c != geometry) {
      reporter->Error(element, what + " has several <geometry> elements; expected one");
    } else if (tag == "drake:proximity_properties") {
      reporter->Warn(element, what + ": " + Tag(*c) +
                                  " ignored (contact parameters come from the problem or scene)");
    } else if (tag != "geometry" && tag != "origin") {
      reporter->Error(element, what + " has an unsupported element " + Tag(*c) + " (line " +
                                   std::to_string(c->Row()) + ")");
    }
  }
  if (geometry == nullptr) reporter->Error(element, what + " has no <geometry>");
  CheckStructuralElement(*geometry, {}, element, reporter);
  if (!ReadShape(*geometry, element, what, false, reporter, &collision->shape)) return false;
  collision->X_LG = ReadOrigin(e, element, what, *reporter);
  return true;
}

/// Reads one <visual>: checked, not kept (idto has no visual geometry).
void ReadVisual(const TiXmlElement& e, const std::string& link, int position,
                UrdfReporter* reporter) {
  const std::string element = LinkElement(link);
  const char* name = e.Attribute("name");
  const std::string what =
      Describe("visual", name != nullptr ? std::string(name) : "#" + std::to_string(position), e);
  CheckStructuralElement(e, {"name"}, element, reporter);
  for (const TiXmlElement* c = e.FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    const std::string tag = c->Value();
    if (tag != "geometry" && tag != "origin" && tag != "material") {
      reporter->Unsupported(element, what + " has an unsupported element " + Tag(*c), true);
    }
  }
  const TiXmlElement* geometry = e.FirstChildElement("geometry");
  if (geometry == nullptr) {
    reporter->Unsupported(element, what + " has no <geometry>", true);
    return;
  }
  CheckStructuralElement(*geometry, {}, element, reporter);
  Shape shape;
  ReadShape(*geometry, element, what, true, reporter, &shape);
  ReadOrigin(e, element, what, *reporter);
}

}  // namespace

UrdfLink ReadLink(const TiXmlElement& e, UrdfReporter* reporter) {
  UrdfLink link;
  link.line = e.Row();
  if (const char* name = e.Attribute("name")) link.name = name;
  if (link.name.empty()) {
    reporter->Error("link (line " + std::to_string(link.line) + ")",
                    "the <link> has no name attribute");
  }
  const std::string element = LinkElement(link.name);
  CheckStructuralElement(e, {"name"}, element, reporter);
  int collisions = 0;
  int visuals = 0;
  for (const TiXmlElement* c = e.FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    const std::string tag = c->Value();
    if (tag == "inertial") {
      if (link.has_inertial) {
        reporter->Error(element, "several <inertial> elements (line " + std::to_string(c->Row()) +
                                     "); expected at most one");
      }
      link.inertia = ReadInertial(*c, element, reporter);
      link.has_inertial = true;
    } else if (tag == "collision") {
      UrdfCollision collision;
      if (ReadCollision(*c, link.name, collisions++, reporter, &collision)) {
        link.collisions.push_back(collision);
      }
    } else if (tag == "visual") {
      ReadVisual(*c, link.name, visuals++, reporter);
    } else {
      reporter->Error(element, "unsupported element " + Tag(*c) + " (line " +
                                   std::to_string(c->Row()) +
                                   "); a <link> may hold <inertial>, <collision> and <visual>");
    }
  }
  return link;
}

}  // namespace urdf_internal
}  // namespace idto
