#pragma once

// The URDF document as idto reads it (private to src/parsers).
//
// The text is read with TinyXML: every element under <robot> is either used, or reported through
// a UrdfReporter (an error, or a warning when it is ignored by design or downgraded by
// UrdfOptions). Numbers are parsed strictly ("0.O5" is an error naming the attribute and the
// text; "nan" is the value nan, refused by the range checks that follow).

#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/geometry/shape.hpp"
#include "idto/multibody/model.hpp"
#include "idto/parsers/urdf.hpp"

class TiXmlElement;

namespace idto {
namespace urdf_internal {

/// Errors (FileError naming the source and the element) and warnings for one parse. With a
/// non-empty `prefix` (UrdfOptions::prefix), a warning's element also names what it is about in
/// the model ("link 'base' (the model's link 'left_base')"), so the warnings of one file loaded
/// twice under two prefixes tell which copy they are about.
class UrdfReporter {
 public:
  UrdfReporter(std::string source, bool unsupported_visuals_are_warnings, std::string prefix,
               std::vector<UrdfWarning>* warnings)
      : source_(std::move(source)),
        visual_warnings_(unsupported_visuals_are_warnings),
        prefix_(std::move(prefix)),
        warnings_(warnings) {}

  const std::string& source() const { return source_; }
  /// Throws FileError "source: element: problem".
  [[noreturn]] void Error(const std::string& element, const std::string& problem) const;
  /// Records a warning (ignored by design, or a downgraded unsupported visual element).
  void Warn(const std::string& element, const std::string& problem);
  /// Something idto cannot represent: an error, or for visual-only elements with
  /// UrdfOptions::unsupported_visuals_as_warnings, a warning.
  void Unsupported(const std::string& element, const std::string& problem, bool visual_only);
  /// The warnings recorded so far.
  const std::vector<UrdfWarning>& warnings() const { return recorded_; }

 private:
  // `element` with, under a prefix, the prefixed name of its link or joint (or the prefix).
  std::string InModel(const std::string& element) const;

  std::string source_;
  bool visual_warnings_{false};
  std::string prefix_;
  std::vector<UrdfWarning>* warnings_{nullptr};
  std::vector<UrdfWarning> recorded_;
};

/// Throws FileError when the elements of `xml` are nested deeper than `max_depth` (checked by a
/// linear scan before any recursive parser sees the text).
void CheckXmlDepth(const std::string& xml, const std::string& source, int max_depth);

// ---- Attributes, read strictly. ----

/// "'name'".
std::string Quoted(std::string_view name);
/// "link 'name'", "joint 'name'".
std::string LinkElement(const std::string& name);
std::string JointElement(const std::string& name);
/// "(x, y, z)".
std::string FormatVector(const Eigen::Vector3d& v);

/// Reads attribute `attribute` of `e` as one number; `fallback` when absent. Text that is not
/// exactly one number is an error naming `element`, "<tag attribute>" and the text.
double ReadNumber(const TiXmlElement& e, const char* attribute, double fallback,
                  const std::string& element, const UrdfReporter& reporter);
/// As ReadNumber, but the attribute must be present.
double ReadRequiredNumber(const TiXmlElement& e, const char* attribute, const std::string& element,
                          const UrdfReporter& reporter);
/// Reads three numbers ("x y z"); `fallback` when absent.
Eigen::Vector3d ReadVector3(const TiXmlElement& e, const char* attribute,
                            const Eigen::Vector3d& fallback, const std::string& element,
                            const UrdfReporter& reporter);
/// The pose given by `parent`'s <origin xyz rpy> child (identity when absent); checked finite.
Eigen::Isometry3d ReadOrigin(const TiXmlElement& parent, const std::string& element,
                             const std::string& what, const UrdfReporter& reporter);
/// "<tag>" of an element.
std::string Tag(const TiXmlElement& e);

// ---- What an element may hold. ----

/// A value element (<origin>, <axis>, <limit>, <dynamics>, <mass>, <inertia>, <parent>,
/// <child>, a shape): only the attributes in `allowed`, no text, no child element. Anything else
/// is an error naming `element`, the tag, its line and what was found: a misspelt optional
/// attribute (<origin ryp="...">, <axis xzy="...">) would otherwise silently take its default.
void CheckValueElement(const TiXmlElement& e, std::initializer_list<std::string_view> allowed,
                       const std::string& element, const UrdfReporter& reporter);

/// A structural element (<robot>, <link>, <joint>, <inertial>, <collision>, <visual>,
/// <geometry>): text is an error; an attribute not in `allowed` (nor an xmlns declaration) is
/// ignored with a warning.
void CheckStructuralElement(const TiXmlElement& e, std::initializer_list<std::string_view> allowed,
                            const std::string& element, UrdfReporter* reporter);

// ---- The document. ----

/// One <collision> element with a shape idto supports.
struct UrdfCollision {
  std::string name;  ///< <collision name>, or "<link>_collision_<i>" (i: position in the link)
  Eigen::Isometry3d X_LG{Eigen::Isometry3d::Identity()};
  Shape shape;
};

struct UrdfLink {
  std::string name;
  int line{0};
  bool has_inertial{false};
  BodyInertia inertia;  ///< in the link frame (zero without <inertial>)
  std::vector<UrdfCollision> collisions;
};

struct UrdfJoint {
  std::string name;
  std::string type;
  std::string parent;
  std::string child;
  int line{0};
  JointSpec spec;  ///< name, type, X_PJ, axis, damping and limits (no prefix, no base pose)
};

/// The tree as written in the document: links and joints in document order.
struct UrdfDocument {
  std::string robot_name;
  std::vector<UrdfLink> links;
  std::vector<UrdfJoint> joints;
  std::map<std::string, int> link_index;                 // name -> index in links
  std::map<std::string, int> parent_joint;               // child link name -> index in joints
  std::map<std::string, std::vector<int>> child_joints;  // link name -> joints, document order
  std::string root;
  /// True when joints name a parent link "world" that the document does not declare (the
  /// world link is then added, massless, as the root).
  bool implicit_world{false};

  const UrdfLink& link(const std::string& name) const {
    return links[static_cast<size_t>(link_index.at(name))];
  }
};

/// Reads one <link> (inertial, collision, visual); see urdf_link.cpp.
UrdfLink ReadLink(const TiXmlElement& e, UrdfReporter* reporter);

/// Reads one <joint>; see urdf_joint.cpp.
UrdfJoint ReadJoint(const TiXmlElement& e, UrdfReporter* reporter);

/// Reads and checks the whole document (a tree with one root); see urdf_document.cpp.
UrdfDocument ReadUrdfDocument(const std::string& xml, UrdfReporter* reporter);

/// Reads `xml` with urdfdom too (its messages captured, not printed). When urdfdom accepts the
/// file, it must not have found links, joints or collision shapes that `doc` lacks; a
/// difference is a FileError (an idto bug: please report it). urdfdom refuses some files idto
/// reads (an implicit world, a revolute joint without <limit>, a capsule): those are not
/// compared.
void CrossCheckWithUrdfdom(const std::string& xml, const UrdfDocument& doc,
                           const UrdfReporter& reporter);

}  // namespace urdf_internal
}  // namespace idto
