// URDF reading helpers: the reporter, the nesting-depth bound, and strict attribute parsing.

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <vector>

#include <tinyxml.h>

#include "idto/core/errors.hpp"
#include "urdf_document.hpp"

namespace idto {
namespace urdf_internal {

void UrdfReporter::Error(const std::string& element, const std::string& problem) const {
  ThrowFileError(source_, element, problem);
}

std::string UrdfReporter::InModel(const std::string& element) const {
  if (prefix_.empty()) return element;
  // The elements of links and joints are LinkElement(name) and JointElement(name); every link
  // and joint name gets the prefix in the model.
  for (const std::string kind : {"link", "joint"}) {
    const std::string head = kind + " '";
    if (element.size() > head.size() && element.compare(0, head.size(), head) == 0 &&
        element.back() == '\'') {
      const std::string name = element.substr(head.size(), element.size() - head.size() - 1);
      return element + " (the model's " + kind + " " + Quoted(prefix_ + name) + ")";
    }
  }
  return element + " (loaded with prefix " + Quoted(prefix_) + ")";
}

void UrdfReporter::Warn(const std::string& element, const std::string& problem) {
  UrdfWarning warning{source_, InModel(element), problem};
  recorded_.push_back(warning);
  if (warnings_ != nullptr) warnings_->push_back(warning);
}

void UrdfReporter::Unsupported(const std::string& element, const std::string& problem,
                               bool visual_only) {
  if (visual_only && visual_warnings_) {
    Warn(element, problem + "; ignored (UrdfOptions::unsupported_visuals_as_warnings)");
    return;
  }
  std::string message = problem;
  if (visual_only) {
    message +=
        " (set UrdfOptions::unsupported_visuals_as_warnings to ignore unsupported visual "
        "elements with a warning)";
  }
  Error(element, message);
}

// ------------------------------------------------------------------------------------------------
// Nesting depth, by a linear scan: TinyXML and urdfdom parse recursively, so a document nested
// 200 000 deep would overflow the stack.

namespace {

/// Index just past the end of the construct that starts at `i` with `open` and ends with
/// `close`; npos when it does not end.
size_t SkipPast(const std::string& xml, size_t i, const char* close) {
  const size_t end = xml.find(close, i);
  return end == std::string::npos ? end : end + std::char_traits<char>::length(close);
}

/// Index just past the '>' that closes the tag starting at `i`, skipping quoted attribute values;
/// sets *self_closing when the tag ends with "/>".
size_t SkipTag(const std::string& xml, size_t i, bool* self_closing) {
  char quote = 0;
  for (size_t k = i; k < xml.size(); ++k) {
    const char c = xml[k];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '>') {
      *self_closing = k > i && xml[k - 1] == '/';
      return k + 1;
    }
  }
  return std::string::npos;
}

}  // namespace

void CheckXmlDepth(const std::string& xml, const std::string& source, int max_depth) {
  int depth = 0;
  int line = 1;
  size_t i = 0;
  size_t counted = 0;  // line numbers are counted up to here
  auto line_at = [&](size_t k) {
    for (; counted < k && counted < xml.size(); ++counted) line += xml[counted] == '\n' ? 1 : 0;
    return line;
  };
  while (i < xml.size()) {
    const size_t lt = xml.find('<', i);
    if (lt == std::string::npos || lt + 1 >= xml.size()) return;
    const char next = xml[lt + 1];
    if (xml.compare(lt, 4, "<!--") == 0) {
      i = SkipPast(xml, lt + 4, "-->");
    } else if (xml.compare(lt, 9, "<![CDATA[") == 0) {
      i = SkipPast(xml, lt + 9, "]]>");
    } else if (next == '?') {
      i = SkipPast(xml, lt + 2, "?>");
    } else if (next == '!') {
      i = SkipPast(xml, lt + 2, ">");
    } else if (next == '/') {
      i = SkipPast(xml, lt + 2, ">");
      if (depth > 0) --depth;
    } else {
      bool self_closing = false;
      i = SkipTag(xml, lt + 1, &self_closing);
      if (!self_closing && ++depth > max_depth) {
        ThrowFileError(source, "XML",
                       "elements nested more than " + std::to_string(max_depth) +
                           " deep (at line " + std::to_string(line_at(lt)) +
                           "); a URDF needs about 5 levels");
      }
    }
    // Unterminated constructs are left for the XML parser to report.
    if (i == std::string::npos) return;
  }
}

// ------------------------------------------------------------------------------------------------
// Attributes.

std::string Quoted(std::string_view name) { return "'" + std::string(name) + "'"; }
std::string LinkElement(const std::string& name) { return "link " + Quoted(name); }
std::string JointElement(const std::string& name) { return "joint " + Quoted(name); }

std::string FormatVector(const Eigen::Vector3d& v) {
  return "(" + FormatValue(v.x()) + ", " + FormatValue(v.y()) + ", " + FormatValue(v.z()) + ")";
}

std::string Tag(const TiXmlElement& e) { return "<" + std::string(e.Value()) + ">"; }

namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// Splits on XML white space.
std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> words;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && IsSpace(text[i])) ++i;
    size_t j = i;
    while (j < text.size() && !IsSpace(text[j])) ++j;
    if (j > i) words.push_back(text.substr(i, j - i));
    i = j;
  }
  return words;
}

/// One number, the whole word: "1e-3", "-2", "+0.5", "nan", "inf". False for "0.O5", "1O", "".
bool ParseWord(const std::string& word, double* value) {
  const char* begin = word.data();
  const char* end = begin + word.size();
  if (begin != end && *begin == '+') ++begin;
  const std::from_chars_result r = std::from_chars(begin, end, *value);
  if (r.ec == std::errc::result_out_of_range) {
    // Beyond double range: keep the sign, let the range checks report the value.
    *value = (begin != end && *begin == '-') ? -HUGE_VAL : HUGE_VAL;
    return r.ptr == end;
  }
  return r.ec == std::errc() && r.ptr == end;
}

std::string AttributeName(const TiXmlElement& e, const char* attribute) {
  return "<" + std::string(e.Value()) + " " + attribute + ">";
}

/// Parses `count` numbers from attribute text; an error naming the attribute and the text.
std::vector<double> ParseNumbers(const TiXmlElement& e, const char* attribute, const char* text,
                                 size_t count, const std::string& element,
                                 const UrdfReporter& reporter) {
  const std::vector<std::string> words = Split(text);
  std::vector<double> values(words.size());
  bool ok = words.size() == count;
  for (size_t i = 0; ok && i < words.size(); ++i) ok = ParseWord(words[i], &values[i]);
  if (!ok) {
    const std::string expected = count == 1 ? "a number" : std::to_string(count) + " numbers";
    reporter.Error(element, AttributeName(e, attribute) + " is \"" + text + "\"; expected " +
                                expected + " (line " + std::to_string(e.Row()) + ")");
  }
  return values;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// What an element may hold.

namespace {

std::string Line(const TiXmlNode& n) { return "(line " + std::to_string(n.Row()) + ")"; }

std::string Join(std::initializer_list<std::string_view> names) {
  std::string list;
  for (std::string_view n : names) list += (list.empty() ? "" : ", ") + std::string(n);
  return list.empty() ? std::string("none") : list;
}

bool Allowed(const std::string& name, std::initializer_list<std::string_view> allowed) {
  for (std::string_view a : allowed) {
    if (name == a) return true;
  }
  return false;
}

/// The text, shortened for a message.
std::string Excerpt(const std::string& text) {
  std::string t = text.size() > 40 ? text.substr(0, 40) + "..." : text;
  return "\"" + t + "\"";
}

/// Text (or CDATA) inside `e` is an error: URDF values are attributes.
void CheckNoText(const TiXmlElement& e, const std::string& element, const UrdfReporter& reporter) {
  for (const TiXmlNode* n = e.FirstChild(); n != nullptr; n = n->NextSibling()) {
    if (const TiXmlText* text = n->ToText()) {
      reporter.Error(element, Tag(e) + " " + Line(e) + " holds the text " +
                                  Excerpt(text->ValueStr()) +
                                  "; expected none (URDF values are attributes)");
    }
  }
}

}  // namespace

void CheckValueElement(const TiXmlElement& e, std::initializer_list<std::string_view> allowed,
                       const std::string& element, const UrdfReporter& reporter) {
  for (const TiXmlAttribute* a = e.FirstAttribute(); a != nullptr; a = a->Next()) {
    if (!Allowed(a->Name(), allowed)) {
      reporter.Error(element, Tag(e) + " " + Line(e) + " has an unknown attribute " + a->Name() +
                                  "=" + Excerpt(a->Value()) + "; expected " + Join(allowed));
    }
  }
  CheckNoText(e, element, reporter);
  if (const TiXmlElement* child = e.FirstChildElement()) {
    reporter.Error(element, Tag(e) + " " + Line(e) + " holds an element " + Tag(*child) + " " +
                                Line(*child) + "; expected none");
  }
}

void CheckStructuralElement(const TiXmlElement& e, std::initializer_list<std::string_view> allowed,
                            const std::string& element, UrdfReporter* reporter) {
  for (const TiXmlAttribute* a = e.FirstAttribute(); a != nullptr; a = a->Next()) {
    const std::string name = a->Name();
    if (Allowed(name, allowed) || name.rfind("xmlns", 0) == 0) continue;
    reporter->Warn(element, "attribute " + name + "=" + Excerpt(a->Value()) + " of " + Tag(e) +
                                " " + Line(e) + " ignored (not a URDF attribute of " + Tag(e) +
                                "; expected " + Join(allowed) + ")");
  }
  CheckNoText(e, element, *reporter);
}

double ReadNumber(const TiXmlElement& e, const char* attribute, double fallback,
                  const std::string& element, const UrdfReporter& reporter) {
  const char* text = e.Attribute(attribute);
  if (text == nullptr) return fallback;
  return ParseNumbers(e, attribute, text, 1, element, reporter)[0];
}

double ReadRequiredNumber(const TiXmlElement& e, const char* attribute, const std::string& element,
                          const UrdfReporter& reporter) {
  if (e.Attribute(attribute) == nullptr) {
    reporter.Error(element, AttributeName(e, attribute) + " is missing (line " +
                                std::to_string(e.Row()) + ")");
  }
  return ReadNumber(e, attribute, 0.0, element, reporter);
}

Eigen::Vector3d ReadVector3(const TiXmlElement& e, const char* attribute,
                            const Eigen::Vector3d& fallback, const std::string& element,
                            const UrdfReporter& reporter) {
  const char* text = e.Attribute(attribute);
  if (text == nullptr) return fallback;
  const std::vector<double> v = ParseNumbers(e, attribute, text, 3, element, reporter);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Eigen::Isometry3d ReadOrigin(const TiXmlElement& parent, const std::string& element,
                             const std::string& what, const UrdfReporter& reporter) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  const TiXmlElement* origin = parent.FirstChildElement("origin");
  if (origin == nullptr) return X;
  if (origin->NextSiblingElement("origin") != nullptr) {
    reporter.Error(element, what + " has several <origin> elements; expected at most one");
  }
  CheckValueElement(*origin, {"xyz", "rpy"}, element, reporter);
  const Eigen::Vector3d xyz =
      ReadVector3(*origin, "xyz", Eigen::Vector3d::Zero(), element, reporter);
  const Eigen::Vector3d rpy =
      ReadVector3(*origin, "rpy", Eigen::Vector3d::Zero(), element, reporter);
  if (!xyz.allFinite() || !rpy.allFinite()) {
    reporter.Error(element, what + " <origin> is not finite: xyz = " + FormatVector(xyz) +
                                ", rpy = " + FormatVector(rpy));
  }
  // URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
  X.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  X.translation() = xyz;
  return X;
}

}  // namespace urdf_internal
}  // namespace idto
