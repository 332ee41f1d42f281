// The architecture's rules, checked on the source tree (docs/architecture.md):
//  - includes run one way: core → math → geometry → multibody → {parsers, contact} → problem →
//    solver → sim → mpc → config → viz; parsers and contact do not include each other;
//  - no file over 800 lines and no function over 100 lines, in include/ and src/ and in the
//    programs, bindings and tests (examples/, benchmarks/, python/src/, tests/).
// A test of the tree rather than of behaviour: it fails on an upward include or an oversized
// file or function, naming it.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace idto {
namespace {

namespace fs = std::filesystem;

const std::map<std::string, int> kLayer = {{"core", 0},      {"math", 1},    {"geometry", 2},
                                           {"multibody", 3}, {"parsers", 4}, {"contact", 4},
                                           {"problem", 5},   {"solver", 6},  {"sim", 7},
                                           {"mpc", 8},       {"config", 9},  {"viz", 10}};

// The folders outside the library whose sources the size rules cover too (a TEST body counts as a
// function).
const char* const kProgramFolders[] = {"examples", "benchmarks", "python/src", "tests"};

struct SourceFile {
  fs::path path;
  std::string module;  // the first folder under the base (include/idto/, src/, examples/, ...)
  std::vector<std::string> lines;
};

// The C++ sources (.hpp, .cpp, .h) under the base folders.
std::vector<SourceFile> CollectFiles(const std::vector<fs::path>& bases) {
  std::vector<SourceFile> out;
  for (const fs::path& base : bases) {
    for (const auto& entry : fs::recursive_directory_iterator(base)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".hpp" && ext != ".cpp" && ext != ".h")) continue;
      const fs::path rel = fs::relative(entry.path(), base);
      SourceFile f;
      f.path = entry.path();
      f.module = rel.has_parent_path() ? rel.begin()->string() : "";
      std::ifstream in(entry.path());
      for (std::string line; std::getline(in, line);) f.lines.push_back(line);
      out.push_back(std::move(f));
    }
  }
  return out;
}

// The library's sources: the layer order applies to them.
std::vector<SourceFile> CollectSources() {
  const fs::path root = IDTO_SOURCE_DIR;
  return CollectFiles({root / "include" / "idto", root / "src"});
}

// The library's sources and the programs' and bindings': the size rules apply to them.
std::vector<SourceFile> CollectSizeCheckedSources() {
  std::vector<SourceFile> out = CollectSources();
  for (const char* folder : kProgramFolders) {
    std::vector<SourceFile> more = CollectFiles({fs::path(IDTO_SOURCE_DIR) / folder});
    EXPECT_FALSE(more.empty()) << folder << ": no sources for the size rules";
    out.insert(out.end(), std::make_move_iterator(more.begin()),
               std::make_move_iterator(more.end()));
  }
  return out;
}

TEST(Layers, SourcesWereFound) {
  const std::vector<SourceFile> files = CollectSources();
  EXPECT_GT(files.size(), 50u);
  for (const SourceFile& f : files) {
    if (f.module.empty()) continue;  // idto.hpp, the umbrella header
    EXPECT_TRUE(kLayer.count(f.module))
        << f.path << ": module '" << f.module << "' has no place in the layer order";
  }
}

TEST(Layers, NoUpwardInclude) {
  const std::regex include_re(R"re(^\s*#\s*include\s+"(?:idto/)?([a-z_]+)/)re");
  for (const SourceFile& f : CollectSources()) {
    const auto own = kLayer.find(f.module);
    if (own == kLayer.end()) continue;
    for (size_t i = 0; i < f.lines.size(); ++i) {
      std::smatch m;
      if (!std::regex_search(f.lines[i], m, include_re)) continue;
      const auto other = kLayer.find(m[1].str());
      if (other == kLayer.end()) continue;  // e.g. "plant_internal.hpp" in the same folder
      EXPECT_LE(other->second, own->second)
          << f.path.string() << ":" << i + 1 << ": module " << f.module << " includes "
          << m[1].str() << ", which sits above it";
      const bool sideways = (f.module == "parsers" && m[1].str() == "contact") ||
                            (f.module == "contact" && m[1].str() == "parsers");
      EXPECT_FALSE(sideways) << f.path.string() << ":" << i + 1
                             << ": parsers and contact must not include each other";
    }
  }
}

TEST(Layers, NoFileOver800Lines) {
  for (const SourceFile& f : CollectSizeCheckedSources()) {
    EXPECT_LE(f.lines.size(), 800u)
        << f.path.string() << ":801: a file of " << f.lines.size() << " lines";
  }
}

// Strips string and character literals and comments from a line (block comments tracked across
// lines through *in_comment).
std::string StripLiterals(const std::string& line, bool* in_comment) {
  std::string out;
  for (size_t i = 0; i < line.size(); ++i) {
    if (*in_comment) {
      if (line.compare(i, 2, "*/") == 0) {
        *in_comment = false;
        ++i;
      }
      continue;
    }
    if (line.compare(i, 2, "//") == 0) break;
    if (line.compare(i, 2, "/*") == 0) {
      *in_comment = true;
      ++i;
      continue;
    }
    if (line[i] == '"' || line[i] == '\'') {
      const char quote = line[i];
      for (++i; i < line.size() && line[i] != quote; ++i) {
        if (line[i] == '\\') ++i;
      }
      continue;
    }
    out += line[i];
  }
  return out;
}

// A function body opens where a '{' follows a ')' (possibly with const/override/noexcept or
// a constructor's initializer list in between) at namespace or class scope.
TEST(Layers, NoFunctionOver100Lines) {
  const std::regex opener_re(
      R"(\)\s*(const|override|final|noexcept|\s)*(->\s*[\w:<>,\s*&]+)?\s*\{\s*$)");
  for (const SourceFile& f : CollectSizeCheckedSources()) {
    if (f.path.filename().string().find("raw_") == 0) continue;
    bool in_comment = false;
    int depth = 0, function_depth = -1;
    size_t function_start = 0;
    std::string previous;
    for (size_t i = 0; i < f.lines.size(); ++i) {
      const std::string code = StripLiterals(f.lines[i], &in_comment);
      const bool opens_function =
          function_depth < 0 && (std::regex_search(code, opener_re) ||
                                 (code.find_first_not_of(" \t") != std::string::npos &&
                                  code.substr(code.find_first_not_of(" \t")) == "{" &&
                                  previous.find(')') != std::string::npos));
      for (char c : code) {
        if (c == '{') {
          if (opens_function && function_depth < 0) {
            function_depth = depth;
            function_start = i;
          }
          ++depth;
        } else if (c == '}') {
          --depth;
          if (depth == function_depth) {
            EXPECT_LE(i - function_start + 1, 100u)
                << f.path.string() << ":" << function_start + 1 << ": a function of "
                << i - function_start + 1 << " lines";
            function_depth = -1;
          }
        }
      }
      if (code.find_first_not_of(" \t") != std::string::npos) previous = code;
    }
  }
}

}  // namespace
}  // namespace idto
