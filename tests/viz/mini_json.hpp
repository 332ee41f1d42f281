#pragma once

// A minimal JSON reader for the viewer's tests (the scene data of a page, the report of its
// test driver). Throws std::runtime_error on malformed text.

#include <cctype>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace idto::test {

struct Json {
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject } type{Type::kNull};
  bool boolean{false};
  double number{0.0};
  std::string string;
  std::vector<Json> array;
  std::map<std::string, Json> object;

  bool is_null() const { return type == Type::kNull; }
  const Json& operator[](const std::string& key) const {
    const auto it = object.find(key);
    if (type != Type::kObject || it == object.end()) throw std::runtime_error("no key " + key);
    return it->second;
  }
  const Json& operator[](std::size_t i) const {
    if (type != Type::kArray || i >= array.size()) throw std::runtime_error("bad index");
    return array[i];
  }
  bool has(const std::string& key) const { return object.count(key) > 0; }
  std::size_t size() const { return type == Type::kArray ? array.size() : object.size(); }
};

class JsonReader {
 public:
  explicit JsonReader(const std::string& text) : s_(text) {}
  Json Parse() {
    Json value = Value();
    Space();
    if (i_ != s_.size()) Fail("trailing text");
    return value;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(i_));
  }
  void Space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool Eat(char c) {
    Space();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  std::string String() {
    if (!Eat('"')) Fail("expected a string");
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c == '\\' && i_ < s_.size()) {
        const char e = s_[i_++];
        if (e == 'u' && i_ + 4 <= s_.size()) {
          const long code = std::strtol(s_.substr(i_, 4).c_str(), nullptr, 16);
          i_ += 4;
          out += code < 0x80 ? static_cast<char>(code) : '?';
          continue;
        }
        c = e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e;
      }
      out += c;
    }
    if (!Eat('"')) Fail("unterminated string");
    return out;
  }
  Json Value() {
    Space();
    Json v;
    if (i_ >= s_.size()) Fail("unexpected end");
    const char c = s_[i_];
    if (c == '{') {
      v.type = Json::Type::kObject;
      ++i_;
      if (Eat('}')) return v;
      do {
        const std::string key = String();
        if (!Eat(':')) Fail("expected ':'");
        v.object[key] = Value();
      } while (Eat(','));
      if (!Eat('}')) Fail("expected '}'");
    } else if (c == '[') {
      v.type = Json::Type::kArray;
      ++i_;
      if (Eat(']')) return v;
      do {
        v.array.push_back(Value());
      } while (Eat(','));
      if (!Eat(']')) Fail("expected ']'");
    } else if (c == '"') {
      v.type = Json::Type::kString;
      v.string = String();
    } else if (s_.compare(i_, 4, "true") == 0 || s_.compare(i_, 5, "false") == 0) {
      v.type = Json::Type::kBool;
      v.boolean = s_[i_] == 't';
      i_ += v.boolean ? 4 : 5;
    } else if (s_.compare(i_, 4, "null") == 0) {
      i_ += 4;
    } else {
      char* end = nullptr;
      v.type = Json::Type::kNumber;
      v.number = std::strtod(s_.c_str() + i_, &end);
      if (end == s_.c_str() + i_) Fail("unexpected character");
      i_ = static_cast<std::size_t>(end - s_.c_str());
    }
    return v;
  }

  const std::string& s_;
  std::size_t i_{0};
};

inline Json ParseJson(const std::string& text) { return JsonReader(text).Parse(); }

/// The text between `begin` and the next `end` after it in `text` (empty when not found).
inline std::string Between(const std::string& text, const std::string& begin,
                           const std::string& end) {
  const std::size_t a = text.find(begin);
  if (a == std::string::npos) return {};
  const std::size_t b = text.find(end, a + begin.size());
  if (b == std::string::npos) return {};
  return text.substr(a + begin.size(), b - a - begin.size());
}

/// The scene data of a page written by WriteHtmlAnimation.
inline Json SceneOfPage(const std::string& page) {
  return ParseJson(
      Between(page, "<script id=\"idto-scene\" type=\"application/json\">", "</script>"));
}

}  // namespace idto::test
