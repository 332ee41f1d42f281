// The URDF document: <robot>, its links and joints, and the checks that they form one tree.

#include "urdf_document.hpp"

#include <set>
#include <string>
#include <vector>

#include <tinyxml.h>

#include "idto/core/errors.hpp"

namespace idto {
namespace urdf_internal {
namespace {

/// Parses the XML (after the nesting-depth check) and returns the <robot> element.
const TiXmlElement& ParseXml(const std::string& xml, const UrdfReporter& reporter,
                             TiXmlDocument* document) {
  CheckXmlDepth(xml, reporter.source(), kMaxUrdfDepth);
  document->Parse(xml.c_str());
  if (document->Error()) {
    std::string problem = std::string("malformed XML: ") + document->ErrorDesc();
    if (document->ErrorRow() > 0) {
      problem += " at line " + std::to_string(document->ErrorRow()) + ", column " +
                 std::to_string(document->ErrorCol());
    }
    reporter.Error("XML", problem);
  }
  const TiXmlElement* robot = document->FirstChildElement("robot");
  if (robot == nullptr) {
    reporter.Error("robot", "no <robot> element found; expected a URDF document");
  }
  // One <robot> and nothing else: TinyXML reads further top-level elements, which would be lost.
  for (const TiXmlNode* n = document->FirstChild(); n != nullptr; n = n->NextSibling()) {
    const TiXmlElement* e = n->ToElement();
    if (n->ToText() != nullptr || (e != nullptr && e != robot)) {
      const std::string found =
          e != nullptr ? Tag(*e) : "text \"" + n->ValueStr().substr(0, 40) + "\"";
      reporter.Error("XML", found + " at the top level (line " + std::to_string(n->Row()) +
                                "), besides the <robot> of line " + std::to_string(robot->Row()) +
                                "; expected one <robot> element and nothing else");
    }
  }
  return *robot;
}

/// Checks the direct children of <robot> that are neither links nor joints.
void CheckRobotChildren(const TiXmlElement& robot, UrdfReporter* reporter) {
  for (const TiXmlElement* c = robot.FirstChildElement(); c != nullptr;
       c = c->NextSiblingElement()) {
    const std::string tag = c->Value();
    const std::string line = " (line " + std::to_string(c->Row()) + ")";
    if (tag == "link" || tag == "joint" || tag == "material") continue;  // material: appearance
    if (tag == "transmission" || tag == "gazebo") {
      const char* name = c->Attribute("name");
      reporter->Warn("robot", Tag(*c) + (name != nullptr ? " " + Quoted(name) : "") + line +
                                  " ignored (actuation is set by the problem's unactuated DoFs)");
    } else if (tag == "drake:collision_filter_group") {
      reporter->Error("robot",
                      Tag(*c) + line + " is not supported; give contact pair filters in the scene");
    } else {
      reporter->Error("robot", "unsupported element " + Tag(*c) + line);
    }
  }
}

void AddLinks(const TiXmlElement& robot, UrdfReporter* reporter, UrdfDocument* doc) {
  for (const TiXmlElement* e = robot.FirstChildElement("link"); e != nullptr;
       e = e->NextSiblingElement("link")) {
    UrdfLink link = ReadLink(*e, reporter);
    const auto [it, inserted] =
        doc->link_index.emplace(link.name, static_cast<int>(doc->links.size()));
    if (!inserted) {
      reporter->Error(LinkElement(link.name),
                      "duplicate link name (lines " +
                          std::to_string(doc->links[static_cast<size_t>(it->second)].line) +
                          " and " + std::to_string(link.line) + "); link names must be unique");
    }
    doc->links.push_back(std::move(link));
  }
  if (doc->links.empty()) reporter->Error("robot", "the robot has no <link> element");
}

void AddJoints(const TiXmlElement& robot, UrdfReporter* reporter, UrdfDocument* doc) {
  std::map<std::string, int> joint_lines;
  for (const TiXmlElement* e = robot.FirstChildElement("joint"); e != nullptr;
       e = e->NextSiblingElement("joint")) {
    UrdfJoint joint = ReadJoint(*e, reporter);
    const std::string element = JointElement(joint.name);
    const auto [it, inserted] = joint_lines.emplace(joint.name, joint.line);
    if (!inserted) {
      reporter->Error(element, "duplicate joint name (lines " + std::to_string(it->second) +
                                   " and " + std::to_string(joint.line) +
                                   "); joint names must be unique");
    }
    if (joint.parent == "world" && doc->link_index.count("world") == 0) {
      // The implicit world link of many URDFs: added, massless, as the root.
      doc->link_index.emplace("world", static_cast<int>(doc->links.size()));
      UrdfLink world;
      world.name = "world";
      doc->links.push_back(world);
      doc->implicit_world = true;
    }
    if (doc->link_index.count(joint.parent) == 0) {
      reporter->Error(element, "parent link '" + joint.parent + "' is not defined");
    }
    if (doc->link_index.count(joint.child) == 0) {
      reporter->Error(element, "child link '" + joint.child + "' is not defined");
    }
    const int index = static_cast<int>(doc->joints.size());
    const auto [pj, first_parent] = doc->parent_joint.emplace(joint.child, index);
    if (!first_parent) {
      reporter->Error(LinkElement(joint.child),
                      "is the child of two joints, '" +
                          doc->joints[static_cast<size_t>(pj->second)].name + "' and '" +
                          joint.name + "'; a URDF must be a tree");
    }
    doc->child_joints[joint.parent].push_back(index);
    doc->joints.push_back(std::move(joint));
  }
}

/// Finds the one root and checks that every link hangs from it.
void FindRoot(const UrdfReporter& reporter, UrdfDocument* doc) {
  std::vector<std::string> roots;
  for (const UrdfLink& link : doc->links) {
    if (doc->parent_joint.count(link.name) == 0) roots.push_back(link.name);
  }
  if (roots.empty()) {
    reporter.Error("robot '" + doc->robot_name + "'",
                   "no root link: every link is the child of a joint (the joints form a cycle)");
  }
  if (roots.size() > 1) {
    std::string list;
    for (const std::string& r : roots) list += (list.empty() ? "" : ", ") + Quoted(r);
    reporter.Error(LinkElement(roots[1]), "several root links (links that are no joint's child): " +
                                              list + "; expected exactly one");
  }
  doc->root = roots.front();
  std::set<std::string> reached = {doc->root};
  std::vector<std::string> stack = {doc->root};
  while (!stack.empty()) {
    const std::string link = stack.back();
    stack.pop_back();
    const auto it = doc->child_joints.find(link);
    if (it == doc->child_joints.end()) continue;
    for (int j : it->second) {
      const std::string& child = doc->joints[static_cast<size_t>(j)].child;
      if (reached.insert(child).second) stack.push_back(child);
    }
  }
  for (const UrdfLink& link : doc->links) {
    if (reached.count(link.name) == 0) {
      reporter.Error(LinkElement(link.name), "is not connected to the root link '" + doc->root +
                                                 "' (its joints form a cycle)");
    }
  }
}

}  // namespace

UrdfDocument ReadUrdfDocument(const std::string& xml, UrdfReporter* reporter) {
  TiXmlDocument document;
  const TiXmlElement& robot = ParseXml(xml, *reporter, &document);
  UrdfDocument doc;
  if (const char* name = robot.Attribute("name")) doc.robot_name = name;
  if (doc.robot_name.empty()) reporter->Error("robot", "the <robot> element has no name attribute");
  CheckStructuralElement(robot, {"name", "version"}, "robot '" + doc.robot_name + "'", reporter);
  CheckRobotChildren(robot, reporter);
  // Only the direct children of <robot> define the tree (<transmission> has <joint> children).
  AddLinks(robot, reporter, &doc);
  AddJoints(robot, reporter, &doc);
  FindRoot(*reporter, &doc);
  return doc;
}

}  // namespace urdf_internal
}  // namespace idto
