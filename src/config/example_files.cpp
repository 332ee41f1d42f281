#include "idto/config/config.hpp"

// Finding example files: by name or path, over the share folders of a program.

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "idto/core/errors.hpp"
#include "yaml_reader.hpp"

namespace idto {

namespace {

namespace fs = std::filesystem;

using config_internal::JoinNames;

bool IsRegularFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

}  // namespace

std::vector<std::string> ListExamples(const std::vector<std::string>& search_dirs) {
  std::set<std::string> names;
  for (const std::string& dir : search_dirs) {
    std::error_code ec;
    const fs::path examples = fs::path(dir) / "examples";
    if (!fs::is_directory(examples, ec)) continue;
    for (const auto& entry : fs::directory_iterator(examples, ec)) {
      const std::string name = entry.path().filename().string();
      if (IsRegularFile(entry.path() / (name + ".yaml"))) names.insert(name);
    }
  }
  return {names.begin(), names.end()};
}

std::string FindExampleConfig(const std::string& name_or_path,
                              const std::vector<std::string>& search_dirs) {
  if (IsRegularFile(name_or_path)) return name_or_path;
  const fs::path p(name_or_path);
  const std::string extension = p.extension().string();
  const bool looks_like_path =
      name_or_path.find('/') != std::string::npos || extension == ".yaml" || extension == ".yml";
  if (name_or_path.empty()) {
    ThrowFileError("<config>", "", "empty name; expected an example name or a YAML file");
  }
  if (looks_like_path) ThrowFileError(name_or_path, "", "no such file");
  std::vector<std::string> searched;
  for (const std::string& dir : search_dirs) {
    const fs::path candidate =
        (fs::path(dir) / "examples" / name_or_path / (name_or_path + ".yaml")).lexically_normal();
    if (IsRegularFile(candidate)) return candidate.string();
    searched.push_back(candidate.string());
  }
  const std::vector<std::string> available = ListExamples(search_dirs);
  ThrowFileError(
      name_or_path, "",
      "no such file or example; searched " +
          (searched.empty() ? std::string("nothing (no search folders)") : JoinNames(searched)) +
          "; examples found: " + (available.empty() ? std::string("none") : JoinNames(available)) +
          " (set IDTO_SHARE_DIR to the folder holding examples/ and models/)");
}

std::vector<std::string> DefaultShareDirs(const std::string& build_tree_dir,
                                          const std::string& executable_path) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("IDTO_SHARE_DIR"); env != nullptr && env[0] != '\0') {
    dirs.emplace_back(env);
  }
  if (!build_tree_dir.empty()) dirs.push_back(build_tree_dir);
  if (!executable_path.empty()) {
    fs::path exe_dir = fs::path(executable_path).parent_path();
    if (exe_dir.empty()) exe_dir = ".";
    dirs.push_back((exe_dir / ".." / "share" / "idto").lexically_normal().string());
  }
  return dirs;
}

}  // namespace idto
