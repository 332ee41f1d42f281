#pragma once

// The one YAML reader of the config layer (private to src/config/). Every section of an example
// file (`scene`, `problem`, `solver`, `mpc` and its sub-sections) is read through these classes
// from the YAML::Node tree of the file itself, so that:
//   - every error is a FileError "<file>: <key path>: <problem> (line L)" with L the line in the
//     file (yaml-cpp marks, 1-based in messages);
//   - the key path spells maps with dots and lists with [i]: "mpc.kp.knee", "scene.models[0]";
//   - conversion errors name the value found and what was expected;
//   - integers are integers ("2.5", "1e300" and "2.0" are errors, not truncated);
//   - unknown and duplicate keys are errors (MapReader, Reader::Entries);
//   - no yaml-cpp exception escapes (ParseYaml converts syntax errors; readers never call
//     YAML::Node::as, and LoadExampleConfigString converts any stray YAML::Exception).

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

namespace idto::config_internal {

/// "path.key", or "key" when `path` is empty.
std::string Join(const std::string& path, const std::string& key);

/// "path[i]".
std::string At(const std::string& path, std::size_t i);

/// "a, b, c", at most `max_names` names (then "... (N in all)").
std::string JoinNames(const std::vector<std::string>& names, std::size_t max_names = 40);

/// `s` without leading and trailing white space.
std::string Trim(const std::string& s);

/// YAML numbers, YAML's .nan/.inf spellings, and multiples of pi: "pi", "-pi", "2*pi",
/// "pi/2", "-0.5*pi/3" (spaces allowed). Returns false when `text` is none of these.
bool ParseNumber(const std::string& text, double* out);

/// How a node reads in a message: "'text'", "a list of 3 entries [1, 2, 3]", "a map", "empty",
/// "missing".
std::string Describe(const YAML::Node& node);

/// Parses YAML text; a syntax error becomes a FileError naming `source_name`, line and column.
YAML::Node ParseYaml(const std::string& text, const std::string& source_name);

/// One key of a map, with its key node (for the key's line) and its value.
struct MapEntry {
  std::string key;
  YAML::Node key_node;
  YAML::Node value;
};

/// Reads values of one file and reports errors naming the file, the key path and the line.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  /// Throws FileError "<file>: <path>: <problem> (line L)", L from `node` when it has a mark.
  [[noreturn]] void Fail(const YAML::Node& node, const std::string& path,
                         const std::string& problem) const;

  /// Fail with the problem "is <found>; expected <expected>".
  [[noreturn]] void FailValue(const YAML::Node& node, const std::string& path,
                              const std::string& found, const std::string& expected) const;

  /// A finite number (ParseNumber's spellings).
  double Double(const YAML::Node& node, const std::string& path) const;
  /// A finite number > 0.
  double Positive(const YAML::Node& node, const std::string& path) const;
  /// A finite number >= 0.
  double NonNegative(const YAML::Node& node, const std::string& path) const;
  /// A decimal integer in [min_value, 1e9]: "2.5", "1e3", "2.0" and "1e300" are errors.
  int Int(const YAML::Node& node, const std::string& path, int min_value) const;
  /// true or false (YAML's spellings).
  bool Bool(const YAML::Node& node, const std::string& path) const;
  /// A scalar, as written.
  std::string String(const YAML::Node& node, const std::string& path) const;
  /// One of `names`; returns its index.
  int Enum(const YAML::Node& node, const std::string& path,
           const std::vector<std::string>& names) const;
  /// A list of exactly `size` finite numbers.
  Eigen::VectorXd Vector(const YAML::Node& node, const std::string& path, int size) const;
  /// A list of exactly 3 finite numbers.
  Eigen::Vector3d Vector3(const YAML::Node& node, const std::string& path) const;
  /// The entries of a map with scalar, unique keys (any names), in file order. `expected`
  /// describes the map for the message when `node` is not a map.
  std::vector<MapEntry> Entries(const YAML::Node& node, const std::string& path,
                                const std::string& expected) const;

 private:
  std::string file_;
};

/// A YAML map whose keys have been checked against an allowed list: unknown keys, duplicate
/// keys and non-scalar keys are errors (each naming the key and its line).
class MapReader {
 public:
  /// Checks `node` (a map at `path`; "" for the top level) against `allowed`.
  MapReader(const Reader& reader, const YAML::Node& node, std::string path,
            const std::vector<std::string>& allowed);

  bool Has(const std::string& key) const { return entries_.count(key) > 0; }
  /// The value of `key` (an undefined node when absent).
  YAML::Node Get(const std::string& key) const;
  /// The key path of `key`: "<path>.<key>".
  std::string Path(const std::string& key) const { return Join(path_, key); }
  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }
  const Reader& reader() const { return reader_; }

  /// The value of `key`; fails when it is absent.
  YAML::Node Require(const std::string& key) const;

  // The value of `key` read as by Reader, or `fallback` when the key is absent.
  double Double(const std::string& key, double fallback) const;
  double Positive(const std::string& key, double fallback) const;
  double NonNegative(const std::string& key, double fallback) const;
  int Int(const std::string& key, int fallback, int min_value) const;
  bool Bool(const std::string& key, bool fallback) const;
  std::string String(const std::string& key, const std::string& fallback) const;
  int Enum(const std::string& key, const std::vector<std::string>& names, int fallback) const;

 private:
  const Reader& reader_;
  YAML::Node node_;
  std::string path_;
  std::map<std::string, YAML::Node> entries_;
};

}  // namespace idto::config_internal
