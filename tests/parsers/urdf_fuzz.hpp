#pragma once

// A fixed-seed mutation fuzzer over the shipped URDF files (models/ and
// tests/data/urdf/reference/): every mutated text must either load into a model with finite
// numbers, or throw a FileError that names the source. Used by urdf_fuzz_test.cpp (a short run) and
// heavy/urdf_fuzz_heavy_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "idto/core/errors.hpp"
#include "idto/parsers/urdf.hpp"

namespace idto {
namespace testing_urdf_fuzz {

inline std::vector<std::string> ShippedUrdfTexts() {
  std::vector<std::string> texts;
  for (const std::string& dir : {std::string(IDTO_SOURCE_DIR) + "/models",
                                 std::string(IDTO_TEST_DATA_DIR) + "/urdf/reference"}) {
    std::vector<std::filesystem::path> paths;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.path().extension() == ".urdf") paths.push_back(entry.path());
    }
    std::sort(paths.begin(), paths.end());  // a fixed order for a fixed seed
    for (const auto& path : paths) {
      std::ifstream in(path);
      std::ostringstream text;
      text << in.rdbuf();
      texts.push_back(text.str());
    }
  }
  return texts;
}

/// One random edit of `text`.
inline std::string Mutate(const std::string& text, std::mt19937* rng) {
  static const std::vector<std::string> kValues = {
      "nan", "inf", "-inf", "-1", "0", "1O", "0.O5", "1e999", "", "1 2", "nan 1 1", "1e-300", "+2"};
  static const std::vector<std::string> kTags = {
      "capsule", "drake:capsule", "mesh", "foo", "sphere", "link", "joint", "inertial", "mimic"};
  std::string s = text;
  auto pick = [&](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(*rng); };
  switch (pick(6)) {
    case 0: {  // an attribute value replaced
      const size_t q = s.find("=\"", pick(s.size()));
      if (q == std::string::npos) break;
      const size_t end = s.find('"', q + 2);
      if (end == std::string::npos) break;
      s.replace(q + 2, end - q - 2, kValues[pick(kValues.size())]);
      break;
    }
    case 1: {  // a few characters deleted
      const size_t at = pick(s.size());
      s.erase(at, 1 + pick(20));
      break;
    }
    case 2: {  // a line duplicated
      const size_t at = s.rfind('\n', pick(s.size()));
      const size_t begin = at == std::string::npos ? 0 : at + 1;
      const size_t end = s.find('\n', begin);
      if (end == std::string::npos) break;
      s.insert(begin, s.substr(begin, end - begin + 1));
      break;
    }
    case 3: {  // a tag renamed
      const size_t lt = s.find('<', pick(s.size()));
      if (lt == std::string::npos || lt + 1 >= s.size() || !std::isalpha(s[lt + 1])) break;
      size_t end = lt + 1;
      while (end < s.size() && (std::isalnum(s[end]) || s[end] == '_' || s[end] == ':')) ++end;
      s.replace(lt + 1, end - lt - 1, kTags[pick(kTags.size())]);
      break;
    }
    case 4: {  // deep nesting inserted
      const size_t at = s.find("</link>", pick(s.size()));
      if (at == std::string::npos) break;
      const size_t depth = 1 + pick(400);
      std::string nest;
      for (size_t i = 0; i < depth; ++i) nest += "<a>";
      for (size_t i = 0; i < depth; ++i) nest += "</a>";
      s.insert(at, nest);
      break;
    }
    default:  // a byte replaced by a printable character
      s[pick(s.size())] = static_cast<char>(32 + pick(95));
      break;
  }
  return s;
}

/// The numbers of a loaded model are finite (limits may be infinite, never NaN).
inline void ExpectFiniteModel(const Model& model) {
  for (int b = 0; b < model.num_bodies(); ++b) {
    const BodyInertia& I = model.body_inertia(b);
    EXPECT_TRUE(std::isfinite(I.mass) && I.p_BBcm.allFinite() && I.I_BBcm_B.allFinite());
  }
  for (const GeometryInstance& g : model.geometries()) {
    EXPECT_TRUE(g.X_BG.matrix().allFinite()) << g.name;
  }
  EXPECT_FALSE(model.position_lower_limits().hasNaN());
  EXPECT_FALSE(model.position_upper_limits().hasNaN());
  EXPECT_FALSE(model.velocity_limits().hasNaN());
  EXPECT_FALSE(model.effort_limits().hasNaN());
}

/// Runs `count` mutations with `seed`; returns how many loaded.
inline int RunUrdfFuzz(unsigned seed, int count) {
  const std::vector<std::string> texts = ShippedUrdfTexts();
  EXPECT_GE(texts.size(), 10u);
  std::mt19937 rng(seed);
  int loaded = 0;
  for (int i = 0; i < count; ++i) {
    const std::string& original = texts[static_cast<size_t>(i) % texts.size()];
    std::string text = Mutate(original, &rng);
    if (i % 3 == 0) text = Mutate(text, &rng);
    const std::string source = "mutant_" + std::to_string(i) + ".urdf";
    try {
      const Model model = ParseUrdfString(text, {}, source);
      ExpectFiniteModel(model);
      ++loaded;
    } catch (const FileError& e) {
      EXPECT_EQ(e.file(), source);
      EXPECT_NE(std::string(e.what()).find(source), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << source << ": unexpected exception: " << e.what() << "\n" << text;
    }
  }
  return loaded;
}

}  // namespace testing_urdf_fuzz
}  // namespace idto
