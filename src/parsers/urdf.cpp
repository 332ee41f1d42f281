#include "idto/parsers/urdf.hpp"

// URDF -> Model.
//
// The text is read twice: once with TinyXML (the XML library urdfdom itself uses) to learn the
// document order of the joints and to check the structure of the tree (names, joint types, parent
// and child links, roots) with precise messages; then with urdfdom for everything else (poses,
// inertias, limits, geometry). urdfdom reports its problems through console_bridge; they are
// captured while it parses and forwarded in the FileError message instead of being printed.
//
// Conventions (see include/idto/parsers/urdf.hpp and models/README.md):
//  - one body per URDF link, added in depth-first order from the root, the children of a link in
//    the document order of their joints; the body frame of a link is its URDF link frame (the
//    joint frame of its parent joint at q = 0);
//  - a root link named "world" stands for the world: its child joints attach to the world body at
//    options.X_WB, its collision geometry goes to the world; options.base is then not used;
//  - collision spheres, boxes and cylinders are kept (boxes replaced by their inscribed spheres
//    when options.box_inscribed_spheres is set); meshes are skipped;
//  - <limit> without lower and upper attributes leaves the position unbounded, effort="0"
//    means no effort limit; velocity limits, <safety_controller>, <calibration>, <mimic> and
//    <transmission> are ignored.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>
#include <Eigen/Eigenvalues>

#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"

namespace idto {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ------------------------------------------------------------------------------------------------
// Messages.

std::string Quoted(const std::string& name) { return "'" + name + "'"; }
std::string LinkElement(const std::string& name) { return "link " + Quoted(name); }
std::string JointElement(const std::string& name) { return "joint " + Quoted(name); }

std::string FormatVector(const Eigen::Vector3d& v) {
  return "(" + FormatValue(v.x()) + ", " + FormatValue(v.y()) + ", " + FormatValue(v.z()) + ")";
}

// ------------------------------------------------------------------------------------------------
// Structure of the document, read with TinyXML.

struct XmlLink {
  std::string name;
  int line{0};
};

struct XmlJoint {
  std::string name;
  std::string type;
  std::string parent;
  std::string child;
  bool has_lower{false};  // <limit lower="...">
  bool has_upper{false};  // <limit upper="...">
  int line{0};
};

/// The tree as written in the document: links and joints in document order.
struct XmlTree {
  std::string robot_name;
  std::vector<XmlLink> links;
  std::vector<XmlJoint> joints;
  std::map<std::string, int> link_index;                 // name -> index in links
  std::map<std::string, int> parent_joint;               // child link name -> index in joints
  std::map<std::string, std::vector<int>> child_joints;  // link name -> joints, document order
  std::string root;
};

std::string LineSuffix(int line) { return " (line " + std::to_string(line) + ")"; }

/// Reads the structure of the document and checks that it is a tree with one root.
XmlTree ReadTree(const std::string& xml, const std::string& source) {
  TiXmlDocument document;
  document.Parse(xml.c_str());
  if (document.Error()) {
    std::string problem = std::string("malformed XML: ") + document.ErrorDesc();
    if (document.ErrorRow() > 0) {
      problem += " at line " + std::to_string(document.ErrorRow()) + ", column " +
                 std::to_string(document.ErrorCol());
    }
    ThrowFileError(source, "XML", problem);
  }
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (robot == nullptr) {
    ThrowFileError(source, "robot", "no <robot> element found; expected a URDF document");
  }
  XmlTree tree;
  if (const char* name = robot->Attribute("name")) tree.robot_name = name;
  if (tree.robot_name.empty()) {
    ThrowFileError(source, "robot", "the <robot> element has no name attribute");
  }

  // Only the direct children of <robot> define the tree (<transmission> has <joint> children).
  for (const TiXmlElement* e = robot->FirstChildElement("link"); e != nullptr;
       e = e->NextSiblingElement("link")) {
    XmlLink link;
    link.line = e->Row();
    if (const char* name = e->Attribute("name")) link.name = name;
    if (link.name.empty()) {
      ThrowFileError(source, "link" + LineSuffix(link.line), "the <link> has no name attribute");
    }
    const auto [it, inserted] =
        tree.link_index.emplace(link.name, static_cast<int>(tree.links.size()));
    if (!inserted) {
      ThrowFileError(source, LinkElement(link.name),
                     "duplicate link name (lines " +
                         std::to_string(tree.links[static_cast<size_t>(it->second)].line) +
                         " and " + std::to_string(link.line) + "); link names must be unique");
    }
    tree.links.push_back(link);
  }
  if (tree.links.empty()) ThrowFileError(source, "robot", "the robot has no <link> element");

  static const std::set<std::string> kKnownTypes = {"revolute", "continuous", "prismatic",
                                                    "fixed",    "floating",   "planar"};
  std::map<std::string, int> joint_lines;
  for (const TiXmlElement* e = robot->FirstChildElement("joint"); e != nullptr;
       e = e->NextSiblingElement("joint")) {
    XmlJoint joint;
    joint.line = e->Row();
    if (const char* name = e->Attribute("name")) joint.name = name;
    if (joint.name.empty()) {
      ThrowFileError(source, "joint" + LineSuffix(joint.line), "the <joint> has no name attribute");
    }
    const std::string element = JointElement(joint.name);
    const auto [it, inserted] = joint_lines.emplace(joint.name, joint.line);
    if (!inserted) {
      ThrowFileError(source, element,
                     "duplicate joint name (lines " + std::to_string(it->second) + " and " +
                         std::to_string(joint.line) + "); joint names must be unique");
    }
    if (const char* type = e->Attribute("type")) joint.type = type;
    if (kKnownTypes.count(joint.type) == 0) {
      ThrowFileError(source, element,
                     "unknown joint type '" + joint.type +
                         "'; expected revolute, continuous, prismatic, fixed, floating or planar");
    }
    const TiXmlElement* parent = e->FirstChildElement("parent");
    const TiXmlElement* child = e->FirstChildElement("child");
    if (parent != nullptr && parent->Attribute("link") != nullptr) {
      joint.parent = parent->Attribute("link");
    }
    if (child != nullptr && child->Attribute("link") != nullptr) {
      joint.child = child->Attribute("link");
    }
    if (joint.parent.empty()) ThrowFileError(source, element, "no <parent link=\"...\"/> given");
    if (joint.child.empty()) ThrowFileError(source, element, "no <child link=\"...\"/> given");
    if (tree.link_index.count(joint.parent) == 0) {
      ThrowFileError(source, element, "parent link '" + joint.parent + "' is not defined");
    }
    if (tree.link_index.count(joint.child) == 0) {
      ThrowFileError(source, element, "child link '" + joint.child + "' is not defined");
    }
    if (joint.parent == joint.child) {
      ThrowFileError(source, element, "connects link '" + joint.child + "' to itself");
    }
    if (const TiXmlElement* limit = e->FirstChildElement("limit")) {
      joint.has_lower = limit->Attribute("lower") != nullptr;
      joint.has_upper = limit->Attribute("upper") != nullptr;
    }
    const int index = static_cast<int>(tree.joints.size());
    const auto [pj, first_parent] = tree.parent_joint.emplace(joint.child, index);
    if (!first_parent) {
      ThrowFileError(source, LinkElement(joint.child),
                     "is the child of two joints, '" +
                         tree.joints[static_cast<size_t>(pj->second)].name + "' and '" +
                         joint.name + "'; a URDF must be a tree");
    }
    tree.child_joints[joint.parent].push_back(index);
    tree.joints.push_back(joint);
  }

  // Roots: links that are nobody's child.
  std::vector<std::string> roots;
  for (const XmlLink& link : tree.links) {
    if (tree.parent_joint.count(link.name) == 0) roots.push_back(link.name);
  }
  if (roots.empty()) {
    ThrowFileError(source, "robot '" + tree.robot_name + "'",
                   "no root link: every link is the child of a joint (the joints form a cycle)");
  }
  if (roots.size() > 1) {
    std::string list;
    for (const std::string& r : roots) list += (list.empty() ? "" : ", ") + Quoted(r);
    ThrowFileError(
        source, LinkElement(roots[1]),
        "several root links (links that are no joint's child): " + list + "; expected exactly one");
  }
  tree.root = roots.front();

  // Every link must hang from the root (a cycle elsewhere leaves links unreached).
  std::set<std::string> reached = {tree.root};
  std::vector<std::string> stack = {tree.root};
  while (!stack.empty()) {
    const std::string link = stack.back();
    stack.pop_back();
    const auto it = tree.child_joints.find(link);
    if (it == tree.child_joints.end()) continue;
    for (int j : it->second) {
      const std::string& child = tree.joints[static_cast<size_t>(j)].child;
      if (reached.insert(child).second) stack.push_back(child);
    }
  }
  for (const XmlLink& link : tree.links) {
    if (reached.count(link.name) == 0) {
      ThrowFileError(
          source, LinkElement(link.name),
          "is not connected to the root link '" + tree.root + "' (its joints form a cycle)");
    }
  }
  return tree;
}

// ------------------------------------------------------------------------------------------------
// urdfdom with its console_bridge messages captured.

/// Collects urdfdom's error messages while a parse runs. It is installed as console_bridge's output
/// handler for the duration of one parse (under a mutex: the handler is global). The object is
/// never destroyed, so console_bridge's "previous handler" pointer can never dangle; outside a
/// parse it forwards to the handler that was current before the last parse.
class CaptureHandler final : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char* filename,
           int line) override {
    if (capturing_) {
      if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_.push_back(text);
      return;
    }
    if (forward_ != nullptr && forward_ != this) forward_->log(text, level, filename, line);
  }

  void Begin() {
    errors_.clear();
    forward_ = console_bridge::getOutputHandler();
    saved_level_ = console_bridge::getLogLevel();
    capturing_ = true;
    console_bridge::useOutputHandler(this);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  }

  void End() {
    console_bridge::setLogLevel(saved_level_);
    console_bridge::restorePreviousOutputHandler();
    capturing_ = false;
  }

  const std::vector<std::string>& errors() const { return errors_; }

 private:
  bool capturing_{false};
  console_bridge::OutputHandler* forward_{nullptr};
  console_bridge::LogLevel saved_level_{console_bridge::CONSOLE_BRIDGE_LOG_WARN};
  std::vector<std::string> errors_;
};

/// Guesses the element (joint or link) that urdfdom's messages are about, e.g. "Joint [j] has no
/// known type" or "link 'a' is not unique"; "robot" when none is named.
std::string ElementFromMessages(const std::vector<std::string>& messages) {
  static const std::regex kPattern(R"((joint|link)\s*(\[([^\]]*)\]|'([^']*)'))", std::regex::icase);
  for (const std::string& message : messages) {
    std::smatch match;
    if (std::regex_search(message, match, kPattern)) {
      std::string kind = match[1].str();
      std::transform(kind.begin(), kind.end(), kind.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      const std::string name = match[3].matched ? match[3].str() : match[4].str();
      return kind + " " + Quoted(name);
    }
  }
  return "robot";
}

urdf::ModelInterfaceSharedPtr ParseWithUrdfdom(const std::string& xml, const std::string& source) {
  static std::mutex mutex;
  static CaptureHandler* const handler = new CaptureHandler();  // never destroyed, see above
  std::vector<std::string> errors;
  urdf::ModelInterfaceSharedPtr model;
  {
    std::lock_guard<std::mutex> lock(mutex);
    handler->Begin();
    try {
      model = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      handler->End();
      ThrowFileError(source, "robot", std::string("urdfdom failed: ") + e.what());
    }
    handler->End();
    errors = handler->errors();
  }
  if (model != nullptr) return model;
  std::string text;
  for (const std::string& e : errors) text += (text.empty() ? "" : "; ") + e;
  if (text.empty()) text = "no message";
  ThrowFileError(source, ElementFromMessages(errors), "urdfdom rejected the file: " + text);
}

// ------------------------------------------------------------------------------------------------
// Conversions and checks.

Eigen::Vector3d ToEigen(const urdf::Vector3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Quaterniond q(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  if (q.norm() > 0.0) q.normalize();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = ToEigen(pose.position);
  return X;
}

bool IsFinite(const Eigen::Isometry3d& X) { return X.matrix().allFinite(); }

void CheckPose(const Eigen::Isometry3d& X, const std::string& source, const std::string& element,
               const std::string& what) {
  if (!IsFinite(X)) {
    ThrowFileError(source, element,
                   what + " is not finite: xyz = " + FormatVector(X.translation()));
  }
}

/// Mass properties of one link in its own frame (zero for a link without <inertial>).
BodyInertia LinkInertia(const urdf::Link& link) {
  BodyInertia inertia;
  if (!link.inertial) return inertia;
  const urdf::Inertial& in = *link.inertial;
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz,  //
      in.ixy, in.iyy, in.iyz,   //
      in.ixz, in.iyz, in.izz;
  const Eigen::Isometry3d X_BI = ToIsometry(in.origin);
  inertia.mass = in.mass;
  inertia.p_BBcm = X_BI.translation();
  const Eigen::Matrix3d R = X_BI.linear();
  inertia.I_BBcm_B = R * I * R.transpose();
  inertia.I_BBcm_B = 0.5 * (inertia.I_BBcm_B + inertia.I_BBcm_B.transpose());
  return inertia;
}

/// Checks what a single link's <inertial> can be checked for on its own.
void CheckLinkInertial(const urdf::Link& link, const std::string& source) {
  if (!link.inertial) return;
  const std::string element = LinkElement(link.name);
  const urdf::Inertial& in = *link.inertial;
  if (!std::isfinite(in.mass) || in.mass < 0.0) {
    ThrowFileError(
        source, element,
        "<inertial> mass is " + FormatValue(in.mass) + "; expected a non-negative number");
  }
  CheckPose(ToIsometry(in.origin), source, element, "<inertial> origin");
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  if (!I.allFinite()) {
    ThrowFileError(source, element, "<inertia> has a non-finite entry");
  }
  const Eigen::Vector3d e = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  const double tol = 1e-9 * std::max(e.cwiseAbs().maxCoeff(), 1e-300);
  if (e(0) < -tol) {
    ThrowFileError(source, element,
                   "<inertia> is not positive semi-definite: principal moments " + FormatVector(e) +
                       "; expected all >= 0");
  }
  if (e(0) + e(1) < e(2) - tol) {
    ThrowFileError(source, element,
                   "<inertia> violates the triangle inequality: principal moments " +
                       FormatVector(e) +
                       "; expected the two smallest to sum to at least the largest");
  }
}

/// Adds the mass properties `b` (in frame C, placed at X_AC in frame A) to `a` (in frame A).
void Accumulate(const BodyInertia& b, const Eigen::Isometry3d& X_AC, BodyInertia* a) {
  if (b.mass <= 0.0 && b.I_BBcm_B.isZero(0.0)) return;
  const double mass = a->mass + b.mass;
  const Eigen::Vector3d p_b = X_AC * b.p_BBcm;
  const Eigen::Matrix3d R = X_AC.linear();
  const Eigen::Matrix3d I_b = R * b.I_BBcm_B * R.transpose();
  if (mass <= 0.0) {
    a->I_BBcm_B += I_b;
    return;
  }
  const Eigen::Vector3d com = (a->mass * a->p_BBcm + b.mass * p_b) / mass;
  auto shift = [](double m, const Eigen::Vector3d& d) -> Eigen::Matrix3d {
    return m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  };
  a->I_BBcm_B = a->I_BBcm_B + shift(a->mass, a->p_BBcm - com) + I_b + shift(b.mass, p_b - com);
  a->p_BBcm = com;
  a->mass = mass;
}

// ------------------------------------------------------------------------------------------------
// The parsed document.

struct ParsedUrdf {
  std::string source;
  XmlTree tree;
  urdf::ModelInterfaceSharedPtr model;
};

ParsedUrdf Parse(const std::string& xml, const std::string& source) {
  ParsedUrdf parsed;
  parsed.source = source;
  parsed.tree = ReadTree(xml, source);
  parsed.model = ParseWithUrdfdom(xml, source);
  return parsed;
}

std::string ReadFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    ThrowFileError(path, "", "file not found");
  }
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

/// Geometry names unique within one call (a repeated <collision name> gets "_1", "_2", ...).
std::string UniqueName(const std::string& name, std::set<std::string>* used) {
  std::string candidate = name;
  for (int k = 1; used->count(candidate) > 0; ++k) candidate = name + "_" + std::to_string(k);
  used->insert(candidate);
  return candidate;
}

struct JointPlan {
  JointSpec spec;
  std::string link;  // URDF name of the child link
};

/// Converts a URDF joint into a JointSpec (without the prefix and the parent pose), checking it.
JointSpec MakeJointSpec(const urdf::Joint& joint, const XmlJoint& xml, const std::string& source) {
  const std::string element = JointElement(joint.name);
  JointSpec spec;
  spec.name = joint.name;
  switch (joint.type) {
    case urdf::Joint::REVOLUTE:
      spec.type = JointType::kRevolute;
      break;
    case urdf::Joint::CONTINUOUS:
      spec.type = JointType::kContinuous;
      break;
    case urdf::Joint::PRISMATIC:
      spec.type = JointType::kPrismatic;
      break;
    case urdf::Joint::FIXED:
      spec.type = JointType::kFixed;
      break;
    case urdf::Joint::FLOATING:
      spec.type = JointType::kFloating;
      break;
    case urdf::Joint::PLANAR:
      spec.type = JointType::kPlanar;
      break;
    default:
      ThrowFileError(source, element,
                     "unknown joint type '" + xml.type +
                         "'; expected revolute, continuous, prismatic, fixed, floating or planar");
  }
  spec.X_PJ = ToIsometry(joint.parent_to_joint_origin_transform);
  CheckPose(spec.X_PJ, source, element, "<origin>");

  const bool has_axis = spec.type == JointType::kRevolute || spec.type == JointType::kContinuous ||
                        spec.type == JointType::kPrismatic || spec.type == JointType::kPlanar;
  if (has_axis) {
    const Eigen::Vector3d axis = ToEigen(joint.axis);
    const double norm = axis.norm();
    if (!std::isfinite(norm) || norm <= 1e-12) {
      ThrowFileError(source, element,
                     "<axis xyz> is " + FormatVector(axis) + "; expected a non-zero finite vector");
    }
    spec.axis = axis / norm;
  }

  if (joint.dynamics) {
    const double damping = joint.dynamics->damping;
    if (!std::isfinite(damping) || damping < 0.0) {
      ThrowFileError(
          source, element,
          "<dynamics damping> is " + FormatValue(damping) + "; expected a non-negative number");
    }
    if (spec.type != JointType::kFixed) spec.damping = damping;
  }

  if (joint.limits && spec.type != JointType::kFixed) {
    const double effort = joint.limits->effort;
    if (std::isnan(effort) || effort < 0.0) {
      ThrowFileError(
          source, element,
          "<limit effort> is " + FormatValue(effort) + "; expected a non-negative number");
    }
    spec.effort_limit = effort > 0.0 ? effort : kInf;  // effort="0" is a common placeholder
    if (spec.type == JointType::kRevolute || spec.type == JointType::kPrismatic) {
      const double lower = xml.has_lower ? joint.limits->lower : -kInf;
      const double upper = xml.has_upper ? joint.limits->upper : kInf;
      if (std::isnan(lower) || std::isnan(upper) || lower > upper) {
        ThrowFileError(source, element,
                       "<limit> lower = " + FormatValue(lower) +
                           " and upper = " + FormatValue(upper) + "; expected lower <= upper");
      }
      if (xml.has_lower || xml.has_upper) {
        spec.lower_limit = lower;
        spec.upper_limit = upper;
      }
    }
  }
  return spec;
}

Shape MakeShape(const urdf::Geometry& geometry, bool* skipped) {
  *skipped = false;
  switch (geometry.type) {
    case urdf::Geometry::SPHERE:
      return Sphere{static_cast<const urdf::Sphere&>(geometry).radius};
    case urdf::Geometry::BOX: {
      Box box;
      box.size = ToEigen(static_cast<const urdf::Box&>(geometry).dim);
      return box;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      return Cylinder{cylinder.radius, cylinder.length};
    }
    default:
      *skipped = true;  // meshes: no analytic contact model
      return Sphere{};
  }
}

void CheckShape(const Shape& shape, const std::string& source, const std::string& element,
                const std::string& geometry_name) {
  auto bad = [&](const std::string& what, double value) {
    ThrowFileError(source, element,
                   "collision '" + geometry_name + "': " + what + " is " + FormatValue(value) +
                       "; expected a finite positive number");
  };
  auto check = [&](const std::string& what, double value) {
    if (!(std::isfinite(value) && value > 0.0)) bad(what, value);
  };
  if (const auto* s = std::get_if<Sphere>(&shape)) check("sphere radius", s->radius);
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    check("cylinder radius", c->radius);
    check("cylinder length", c->length);
  }
  if (const auto* b = std::get_if<Box>(&shape)) {
    for (int i = 0; i < 3; ++i) check("box size(" + std::to_string(i) + ")", b->size(i));
  }
}

[[noreturn]] void RethrowFromBuilder(const std::string& source, const std::string& element,
                                     const std::exception& e) {
  ThrowFileError(source, element, std::string("rejected by ModelBuilder: ") + e.what());
}

BodyIndex AddParsed(const ParsedUrdf& parsed, const UrdfOptions& options, ModelBuilder* builder,
                    const char* where) {
  const std::string& source = parsed.source;
  const XmlTree& tree = parsed.tree;
  const urdf::ModelInterface& model = *parsed.model;
  const std::string& prefix = options.prefix;

  if (!IsFinite(options.X_WB)) {
    ThrowInvalidArgument(where, "options.X_WB", "not finite", "a finite pose");
  }

  auto get_link = [&](const std::string& name) -> const urdf::Link& {
    const urdf::LinkConstSharedPtr link = model.getLink(name);
    if (!link) ThrowFileError(source, LinkElement(name), "missing from urdfdom's model");
    return *link;
  };
  auto get_joint = [&](const std::string& name) -> const urdf::Joint& {
    const urdf::JointConstSharedPtr joint = model.getJoint(name);
    if (!joint) ThrowFileError(source, JointElement(name), "missing from urdfdom's model");
    return *joint;
  };

  // Depth-first order from the root, children in the document order of their joints.
  std::vector<std::string> order;
  {
    std::vector<std::string> stack = {tree.root};
    while (!stack.empty()) {
      const std::string link = stack.back();
      stack.pop_back();
      order.push_back(link);
      const auto it = tree.child_joints.find(link);
      if (it == tree.child_joints.end()) continue;
      for (auto j = it->second.rbegin(); j != it->second.rend(); ++j) {
        stack.push_back(tree.joints[static_cast<size_t>(*j)].child);
      }
    }
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

  const bool world_root = tree.root == "world";
  const BaseType base = options.base;
  if (!world_root && base == BaseType::kPlanar) {
    const double n = options.planar_normal.norm();
    if (!std::isfinite(n) || n <= 1e-12) {
      ThrowInvalidArgument(where, "options.planar_normal", FormatVector(options.planar_normal),
                           "a non-zero finite vector");
    }
  }

  // Joint specs and per-link checks, all before touching the builder.
  std::map<std::string, JointSpec> specs;  // by child link name
  for (const XmlJoint& xml : tree.joints) {
    specs.emplace(xml.child, MakeJointSpec(get_joint(xml.name), xml, source));
  }
  std::map<std::string, BodyInertia> inertias;
  for (const std::string& name : order) {
    const urdf::Link& link = get_link(name);
    CheckLinkInertial(link, source);
    inertias.emplace(name, LinkInertia(link));
  }
  if (world_root) {
    const BodyInertia& w = inertias.at(tree.root);
    if (w.mass != 0.0 || !w.I_BBcm_B.isZero(0.0)) {
      ThrowFileError(source, LinkElement(tree.root),
                     "a root link named 'world' stands for the world and must not have mass or "
                     "inertia (mass " +
                         FormatValue(w.mass) + ")");
    }
  }

  // A moving link (with its welded descendants) needs positive mass and a positive-definite
  // rotational inertia.
  auto is_moving = [&](const std::string& name) {
    if (name == tree.root) return !world_root && base != BaseType::kFixed;
    return specs.at(name).type != JointType::kFixed;
  };
  for (const std::string& name : order) {
    if (!is_moving(name)) continue;
    BodyInertia composite;
    std::vector<std::pair<std::string, Eigen::Isometry3d>> stack = {
        {name, Eigen::Isometry3d::Identity()}};
    int welded = 0;
    while (!stack.empty()) {
      const auto [link, X_LD] = stack.back();
      stack.pop_back();
      Accumulate(inertias.at(link), X_LD, &composite);
      const auto it = tree.child_joints.find(link);
      if (it == tree.child_joints.end()) continue;
      for (int j : it->second) {
        const std::string& child = tree.joints[static_cast<size_t>(j)].child;
        const JointSpec& spec = specs.at(child);
        if (spec.type != JointType::kFixed) continue;
        ++welded;
        stack.emplace_back(child, X_LD * spec.X_PJ);
      }
    }
    const std::string element = LinkElement(name);
    const std::string with_welded = welded > 0 ? " (including its welded child links)" : "";
    if (!(composite.mass > 0.0)) {
      std::string problem;
      if (name == tree.root) {
        problem = std::string("the link is the ") +
                  (base == BaseType::kFloating ? "floating" : "planar") + " base but ";
      } else {
        const XmlJoint& joint = tree.joints[static_cast<size_t>(tree.parent_joint.at(name))];
        problem = "the link moves (" + joint.type + " joint '" + joint.name + "') but ";
      }
      if (get_link(name).inertial == nullptr) {
        problem += "has no <inertial>";
        if (welded > 0) problem += " and its welded child links have no mass either";
      } else {
        problem += "its mass" + with_welded + " is " + FormatValue(composite.mass);
      }
      ThrowFileError(source, element, problem + "; a moving link needs a positive mass");
    }
    const Eigen::Vector3d e =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(composite.I_BBcm_B).eigenvalues();
    if (!(e(0) > 1e-12 * std::max(1.0, composite.I_BBcm_B.trace()))) {
      ThrowFileError(source, element,
                     "the link moves but its rotational inertia about its centre of mass" +
                         with_welded + " is not positive definite: principal moments " +
                         FormatVector(e));
    }
  }

  // Collision geometry, checked and named before anything is added.
  struct PlannedGeometry {
    std::string name;       // prefixed, unique
    std::string urdf_name;  // as in the file (or the default name)
    Eigen::Isometry3d X_LG;
    Shape shape;
  };
  std::map<std::string, std::vector<PlannedGeometry>> geometry_of;
  std::set<std::string> geometry_names;
  for (const std::string& name : order) {
    const urdf::Link& link = get_link(name);
    const std::string element = LinkElement(name);
    for (size_t i = 0; i < link.collision_array.size(); ++i) {
      const urdf::Collision* collision = link.collision_array[i].get();
      if (collision == nullptr || !collision->geometry) continue;
      bool skipped = false;
      const Shape shape = MakeShape(*collision->geometry, &skipped);
      if (skipped) continue;
      PlannedGeometry g;
      g.urdf_name =
          collision->name.empty() ? name + "_collision_" + std::to_string(i) : collision->name;
      g.name = UniqueName(prefix + g.urdf_name, &geometry_names);
      CheckShape(shape, source, element, g.urdf_name);
      g.X_LG = ToIsometry(collision->origin);
      CheckPose(g.X_LG, source, element, "collision '" + g.urdf_name + "' <origin>");
      g.shape = shape;
      const Box* box = std::get_if<Box>(&shape);
      if (box == nullptr || !options.box_inscribed_spheres.has_value()) {
        geometry_of[name].push_back(g);
        continue;
      }
      // The box's inscribed spheres instead of the box, named after the box's (unique) name.
      const std::vector<InscribedSphere> spheres =
          InscribedSpheres(*box, *options.box_inscribed_spheres);
      for (std::size_t k = 0; k < spheres.size(); ++k) {
        PlannedGeometry sphere;
        sphere.urdf_name = g.urdf_name + "_sphere" + std::to_string(k);
        sphere.name = UniqueName(g.name + "_sphere" + std::to_string(k), &geometry_names);
        sphere.X_LG = g.X_LG * spheres[k].X_BoxSphere;
        sphere.shape = spheres[k].sphere;
        geometry_of[name].push_back(sphere);
      }
    }
  }

  // Add the bodies. Only the builder's own checks (e.g. names already used by another model)
  // can fail from here on; the builder then holds the bodies added so far.
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
    if (name == tree.root && world_root) {
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
    JointSpec joint;
    BodyIndex parent = kWorldBody;
    if (name == tree.root) {
      joint.name = name + "_root_joint";
      joint.X_PJ = options.X_WB;
      switch (base) {
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
    } else {
      joint = specs.at(name);
      const std::string& parent_link =
          tree.joints[static_cast<size_t>(tree.parent_joint.at(name))].parent;
      parent = body_of.at(parent_link);
      if (parent == kWorldBody) joint.X_PJ = options.X_WB * joint.X_PJ;
    }
    joint.name = prefix + joint.name;
    BodyIndex body = kWorldBody;
    try {
      body = builder->AddBody(prefix + name, inertias.at(name), parent, joint);
    } catch (const std::invalid_argument& e) {
      RethrowFromBuilder(source, element + " (joint '" + joint.name + "')", e);
    }
    body_of[name] = body;
    if (name == tree.root) root_body = body;
    add_geometry(name, body, Eigen::Isometry3d::Identity());
  }
  return root_body;
}

/// Builds, naming the link a builder error is about when its (prefixed) name appears in the
/// message.
Model BuildModel(const ModelBuilder& builder, const ParsedUrdf& parsed, const std::string& prefix) {
  try {
    return builder.Build();
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    std::string element = "robot '" + parsed.tree.robot_name + "'";
    size_t best = 0;
    for (const XmlLink& link : parsed.tree.links) {
      const std::string name = prefix + link.name;
      if (name.size() > best && message.find(name) != std::string::npos) {
        best = name.size();
        element = LinkElement(link.name);
      }
    }
    RethrowFromBuilder(parsed.source, element, e);
  }
}

Model ParseAndBuild(const std::string& xml, const UrdfOptions& options, const std::string& source,
                    const char* where) {
  const ParsedUrdf parsed = Parse(xml, source);
  ModelBuilder builder(options.model_name.empty() ? parsed.tree.robot_name : options.model_name);
  AddParsed(parsed, options, &builder, where);
  return BuildModel(builder, parsed, options.prefix);
}

}  // namespace

Model ParseUrdfFile(const std::string& path, const UrdfOptions& options) {
  return ParseAndBuild(ReadFile(path), options, path, "ParseUrdfFile");
}

Model ParseUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                      const std::string& source_name) {
  return ParseAndBuild(urdf_xml, options, source_name, "ParseUrdfString");
}

BodyIndex AddUrdfFile(const std::string& path, const UrdfOptions& options, ModelBuilder* builder) {
  if (builder == nullptr) ThrowInvalidArgument("AddUrdfFile", "builder", "null", "a ModelBuilder");
  return AddParsed(Parse(ReadFile(path), path), options, builder, "AddUrdfFile");
}

BodyIndex AddUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                        ModelBuilder* builder, const std::string& source_name) {
  if (builder == nullptr) {
    ThrowInvalidArgument("AddUrdfString", "builder", "null", "a ModelBuilder");
  }
  return AddParsed(Parse(urdf_xml, source_name), options, builder, "AddUrdfString");
}

}  // namespace idto
