#pragma once

// A fixed-seed mutation fuzzer over the shipped example configurations (examples/*/*.yaml):
// every mutated text must either load, and then solve one iteration to a finite result or end
// with a failure status and a message (never NaN in the trajectory, never an exception from the
// solver), or be refused with a FileError that names the source. Used by yaml_fuzz_test.cpp (a
// short run) and heavy/yaml_fuzz_heavy_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "idto/config/config.hpp"
#include "idto/config/mpc_config.hpp"
#include "idto/core/errors.hpp"
#include "idto/solver/trajectory_optimizer.hpp"

namespace idto {
namespace testing_yaml_fuzz {

struct ShippedYaml {
  std::string name;  // example name
  std::string dir;   // its folder (relative URDF paths resolve there)
  std::string text;
};

inline std::vector<ShippedYaml> ShippedYamlTexts() {
  std::vector<ShippedYaml> out;
  std::vector<std::filesystem::path> paths;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(IDTO_SOURCE_DIR) + "/examples")) {
    const std::filesystem::path yaml = entry.path() / (entry.path().filename().string() + ".yaml");
    if (std::filesystem::exists(yaml)) paths.push_back(yaml);
  }
  std::sort(paths.begin(), paths.end());  // a fixed order for a fixed seed
  for (const auto& path : paths) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    out.push_back({path.stem().string(), path.parent_path().string(), text.str()});
  }
  return out;
}

// Start and end of the line holding position `at`.
inline std::pair<size_t, size_t> LineAround(const std::string& s, size_t at) {
  const size_t nl = s.rfind('\n', at);
  const size_t begin = nl == std::string::npos ? 0 : nl + 1;
  size_t end = s.find('\n', begin);
  if (end == std::string::npos) end = s.size();
  return {begin, end};
}

/// One random edit of `text`: a scalar replaced by a bad or extreme one, a line duplicated
/// (duplicate key) or deleted, indentation changed, a key renamed, characters deleted or a byte
/// replaced.
inline std::string Mutate(const std::string& text, std::mt19937* rng) {
  static const std::vector<std::string> kValues = {
      "nan", ".nan", ".inf", "-.inf", "-1",    "0",          "1e300",     "-1e300", "2.5",
      "abc", "",     "~",    "true",  "1e999", "[1, 2]",     "{a: 1}",    "1e-300", "100000000",
      "[]",  "-0",   "0x10", "[nan]", "'1'",   "[1e300, 0]", "2147483648"};
  static const std::vector<std::string> kKeys = {
      "num_steps",   "time_step", "q_init",  "weights", "stiffness", "max_iterations",
      "num_threads", "duration",  "latency", "foo",     "limits"};
  std::string s = text;
  if (s.empty()) return s;
  auto pick = [&](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(*rng); };
  const auto [begin, end] = LineAround(s, pick(s.size()));
  switch (pick(7)) {
    case 0: {  // the value after a key's colon replaced
      const size_t colon = s.find(": ", begin);
      if (colon == std::string::npos || colon >= end) break;
      size_t value_end = s.find(" #", colon);
      if (value_end == std::string::npos || value_end > end) value_end = end;
      s.replace(colon + 2, value_end - colon - 2, kValues[pick(kValues.size())]);
      break;
    }
    case 1:  // a line duplicated: a duplicate key, or a list entry more
      s.insert(begin, s.substr(begin, end - begin) + "\n");
      break;
    case 2:  // a line deleted
      s.erase(begin, std::min(end + 1, s.size()) - begin);
      break;
    case 3:  // indentation changed
      if (pick(2) == 0) {
        s.insert(begin, "  ");
      } else if (s.compare(begin, 2, "  ") == 0) {
        s.erase(begin, 2);
      }
      break;
    case 4: {  // a key renamed
      const size_t colon = s.find(':', begin);
      if (colon == std::string::npos || colon >= end) break;
      size_t key_begin = begin;
      while (key_begin < colon && (s[key_begin] == ' ' || s[key_begin] == '-')) ++key_begin;
      s.replace(key_begin, colon - key_begin, kKeys[pick(kKeys.size())]);
      break;
    }
    case 5:  // a few characters deleted
      s.erase(pick(s.size()), 1 + pick(12));
      break;
    default:  // a byte replaced by a printable character
      s[pick(s.size())] = static_cast<char>(32 + pick(95));
      break;
  }
  return s;
}

/// Loads `text`; when it loads, reads its mpc section and runs one solver iteration on one
/// thread. Returns true when it loaded. Every way out but a clean load or a FileError naming
/// `source` is a test failure.
inline bool LoadAndSolveOnce(const ShippedYaml& yaml, const std::string& text,
                             const std::string& source) {
  ExampleConfig config;
  try {
    config = LoadExampleConfigString(text, source, yaml.dir, {IDTO_SOURCE_DIR});
    if (config.mpc) ParseMpcConfig(config);
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), source) << e.what();
    EXPECT_NE(std::string(e.what()).find(source), std::string::npos) << e.what();
    return false;
  } catch (const std::exception& e) {
    ADD_FAILURE() << source << ": unexpected exception while loading: " << e.what() << "\n" << text;
    return false;
  }
  // Solving a problem a mutation made enormous is a memory and time test, not this one (the
  // loader's size checks have their own tests): solve what fits in a few milliseconds.
  if (static_cast<long>(config.problem.num_steps) * config.model.nq() > 4000) return true;
  try {
    SolverOptions options = config.solver;
    options.max_iterations = 1;
    options.num_threads = 1;
    options.verbosity = 0;
    TrajectoryOptimizer optimizer(config.model, config.problem, options);
    Trajectory solution;
    const SolverSummary summary = optimizer.Solve(MakeInitialGuess(config), &solution);
    if (summary.termination == TerminationType::kFailure) {
      EXPECT_FALSE(summary.message.empty()) << source;
    } else {
      EXPECT_TRUE(std::isfinite(summary.final_cost)) << source << "\n" << text;
      for (const Eigen::VectorXd& q : solution.q) EXPECT_TRUE(q.allFinite()) << source;
      for (const Eigen::VectorXd& tau : solution.tau) EXPECT_TRUE(tau.allFinite()) << source;
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << source
                  << ": the solver threw on a configuration the loader accepted: " << e.what()
                  << "\n"
                  << text;
  }
  return true;
}

/// Runs `count` mutations with `seed`; returns how many loaded.
inline int RunYamlFuzz(unsigned seed, int count) {
  const std::vector<ShippedYaml> files = ShippedYamlTexts();
  EXPECT_GE(files.size(), 10u);
  std::mt19937 rng(seed);
  int loaded = 0;
  for (int i = 0; i < count; ++i) {
    const ShippedYaml& yaml = files[static_cast<size_t>(i) % files.size()];
    std::string text = Mutate(yaml.text, &rng);
    if (i % 3 == 0) text = Mutate(text, &rng);
    const std::string source = "mutant_" + std::to_string(i) + "_" + yaml.name + ".yaml";
    loaded += LoadAndSolveOnce(yaml, text, source) ? 1 : 0;
  }
  return loaded;
}

}  // namespace testing_yaml_fuzz
}  // namespace idto
