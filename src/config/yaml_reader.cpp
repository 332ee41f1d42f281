#include "yaml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <utility>

#include "idto/core/errors.hpp"

namespace idto::config_internal {

namespace {

/// A plain number over the whole string (strtod, C locale).
bool ParsePlainNumber(const std::string& s, double* out) {
  if (s.empty()) return false;
  const char* begin = s.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end != begin + s.size()) return false;
  *out = value;
  return true;
}

/// ".nan", ".inf", "-.inf" and their capitalized spellings.
bool ParseSpecialNumber(const std::string& s, double* out) {
  static const std::set<std::string> kNan = {".nan", ".NaN", ".NAN"};
  static const std::set<std::string> kInf = {".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF"};
  static const std::set<std::string> kNegInf = {"-.inf", "-.Inf", "-.INF"};
  if (kNan.count(s)) {
    *out = std::nan("");
  } else if (kInf.count(s)) {
    *out = INFINITY;
  } else if (kNegInf.count(s)) {
    *out = -INFINITY;
  } else {
    return false;
  }
  return true;
}

}  // namespace

std::string Join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string At(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string JoinNames(const std::vector<std::string>& names, std::size_t max_names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < max_names; ++i) {
    if (i > 0) out += ", ";
    out += names[i];
  }
  if (names.size() > max_names) out += ", ... (" + std::to_string(names.size()) + " in all)";
  return out;
}

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

bool ParseNumber(const std::string& text, double* out) {
  std::string s;
  for (char c : text) {
    if (c != ' ' && c != '\t') s.push_back(c);
  }
  if (s.empty()) return false;
  if (ParseSpecialNumber(s, out)) return true;
  const auto pi_pos = s.find("pi");
  if (pi_pos == std::string::npos) return ParsePlainNumber(s, out);
  const std::string prefix = s.substr(0, pi_pos);
  const std::string suffix = s.substr(pi_pos + 2);
  double factor = 1.0;
  if (prefix == "-") {
    factor = -1.0;
  } else if (prefix.empty() || prefix == "+") {
    factor = 1.0;
  } else if (prefix.back() == '*') {
    if (!ParsePlainNumber(prefix.substr(0, prefix.size() - 1), &factor)) return false;
  } else {
    return false;
  }
  double divisor = 1.0;
  if (!suffix.empty()) {
    if (suffix.front() != '/') return false;
    if (!ParsePlainNumber(suffix.substr(1), &divisor) || divisor == 0.0) return false;
  }
  *out = factor * M_PI / divisor;
  return true;
}

std::string Describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
      return "missing";
    case YAML::NodeType::Null:
      return "empty";
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence: {
      std::string text =
          "a list of " + std::to_string(node.size()) + (node.size() == 1 ? " entry" : " entries");
      YAML::Emitter emitter;
      emitter << YAML::Flow << node;
      const std::string flow = emitter.good() ? std::string(emitter.c_str()) : std::string();
      if (!flow.empty() && flow.size() <= 80) text += " " + flow;
      return text;
    }
    case YAML::NodeType::Map:
      return "a map";
  }
  return "unknown";
}

YAML::Node ParseYaml(const std::string& text, const std::string& source_name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::string problem = e.msg;
    if (e.mark.line >= 0) {
      problem += " (line " + std::to_string(e.mark.line + 1) + ", column " +
                 std::to_string(e.mark.column + 1) + ")";
    }
    ThrowFileError(source_name, "(YAML syntax)", "malformed YAML: " + problem);
  }
}

// ------------------------------------------------------------------------------------- Reader

void Reader::Fail(const YAML::Node& node, const std::string& path,
                  const std::string& problem) const {
  std::string text = problem;
  if (node.IsDefined()) {
    const YAML::Mark mark = node.Mark();
    if (mark.line >= 0) text += " (line " + std::to_string(mark.line + 1) + ")";
  }
  ThrowFileError(file_, path, text);
}

void Reader::FailValue(const YAML::Node& node, const std::string& path, const std::string& found,
                       const std::string& expected) const {
  Fail(node, path, "is " + found + "; expected " + expected);
}

double Reader::Double(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) FailValue(node, path, Describe(node), "a number");
  double value = 0.0;
  if (!ParseNumber(node.Scalar(), &value)) FailValue(node, path, Describe(node), "a number");
  if (!std::isfinite(value)) FailValue(node, path, FormatValue(value), "a finite number");
  return value;
}

double Reader::Positive(const YAML::Node& node, const std::string& path) const {
  const double value = Double(node, path);
  if (!(value > 0.0)) FailValue(node, path, FormatValue(value), "a finite positive number");
  return value;
}

double Reader::NonNegative(const YAML::Node& node, const std::string& path) const {
  const double value = Double(node, path);
  if (!(value >= 0.0)) FailValue(node, path, FormatValue(value), "a finite non-negative number");
  return value;
}

int Reader::Int(const YAML::Node& node, const std::string& path, int min_value) const {
  constexpr long long kMax = 1000000000LL;
  const std::string expected = "an integer >= " + std::to_string(min_value);
  if (!node.IsScalar()) FailValue(node, path, Describe(node), expected);
  const std::string text = Trim(node.Scalar());
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size()) {
    FailValue(node, path, Describe(node), expected);
  }
  if (value < min_value) FailValue(node, path, std::to_string(value), expected);
  if (value > kMax) {
    FailValue(node, path, Describe(node),
              "an integer from " + std::to_string(min_value) + " to " + std::to_string(kMax));
  }
  return static_cast<int>(value);
}

bool Reader::Bool(const YAML::Node& node, const std::string& path) const {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
    FailValue(node, path, Describe(node), "true or false");
  }
  return value;
}

std::string Reader::String(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) FailValue(node, path, Describe(node), "a string");
  return node.Scalar();
}

int Reader::Enum(const YAML::Node& node, const std::string& path,
                 const std::vector<std::string>& names) const {
  const std::string expected = "one of " + JoinNames(names);
  if (!node.IsScalar()) FailValue(node, path, Describe(node), expected);
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (node.Scalar() == names[i]) return static_cast<int>(i);
  }
  FailValue(node, path, Describe(node), expected);
}

Eigen::VectorXd Reader::Vector(const YAML::Node& node, const std::string& path, int size) const {
  const std::string expected =
      "a list of " + std::to_string(size) + (size == 1 ? " number" : " numbers");
  if (!node.IsSequence() || static_cast<int>(node.size()) != size) {
    FailValue(node, path, Describe(node), expected);
  }
  Eigen::VectorXd x(size);
  for (int i = 0; i < size; ++i) x(i) = Double(node[i], At(path, i));
  return x;
}

Eigen::Vector3d Reader::Vector3(const YAML::Node& node, const std::string& path) const {
  return Vector(node, path, 3);
}

std::vector<MapEntry> Reader::Entries(const YAML::Node& node, const std::string& path,
                                      const std::string& expected) const {
  if (!node.IsMap()) FailValue(node, path, Describe(node), expected);
  std::vector<MapEntry> entries;
  std::set<std::string> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    if (!it->first.IsScalar()) {
      FailValue(it->first, path, "a map with key " + Describe(it->first), "string keys");
    }
    const std::string key = it->first.Scalar();
    if (!seen.insert(key).second) Fail(it->first, Join(path, key), "duplicate key");
    entries.push_back({key, it->first, it->second});
  }
  return entries;
}

// ---------------------------------------------------------------------------------- MapReader

MapReader::MapReader(const Reader& reader, const YAML::Node& node, std::string path,
                     const std::vector<std::string>& allowed)
    : reader_(reader), node_(node), path_(std::move(path)) {
  const std::string where = path_.empty() ? std::string("(top level)") : path_;
  for (const MapEntry& e : reader.Entries(node, where, "a map with keys " + JoinNames(allowed))) {
    if (std::find(allowed.begin(), allowed.end(), e.key) == allowed.end()) {
      reader.Fail(e.key_node, Join(path_, e.key),
                  "unknown key; expected one of " + JoinNames(allowed));
    }
    entries_.emplace(e.key, e.value);
  }
}

YAML::Node MapReader::Get(const std::string& key) const {
  auto it = entries_.find(key);
  return it == entries_.end() ? YAML::Node(YAML::NodeType::Undefined) : it->second;
}

YAML::Node MapReader::Require(const std::string& key) const {
  if (!Has(key)) reader_.Fail(node_, Path(key), "missing (required)");
  return Get(key);
}

double MapReader::Double(const std::string& key, double fallback) const {
  return Has(key) ? reader_.Double(Get(key), Path(key)) : fallback;
}

double MapReader::Positive(const std::string& key, double fallback) const {
  return Has(key) ? reader_.Positive(Get(key), Path(key)) : fallback;
}

double MapReader::NonNegative(const std::string& key, double fallback) const {
  return Has(key) ? reader_.NonNegative(Get(key), Path(key)) : fallback;
}

int MapReader::Int(const std::string& key, int fallback, int min_value) const {
  return Has(key) ? reader_.Int(Get(key), Path(key), min_value) : fallback;
}

bool MapReader::Bool(const std::string& key, bool fallback) const {
  return Has(key) ? reader_.Bool(Get(key), Path(key)) : fallback;
}

std::string MapReader::String(const std::string& key, const std::string& fallback) const {
  return Has(key) ? reader_.String(Get(key), Path(key)) : fallback;
}

int MapReader::Enum(const std::string& key, const std::vector<std::string>& names,
                    int fallback) const {
  return Has(key) ? reader_.Enum(Get(key), Path(key), names) : fallback;
}

}  // namespace idto::config_internal
