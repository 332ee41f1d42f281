#pragma once

// idto-run's JSON writer (its summary files) and the number format of its text and CSV output.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "run/json_text.hpp"

namespace idto::examples {

/// A minimal JSON writer: objects and arrays with commas handled, strings escaped, non-finite
/// numbers written as null.
class JsonWriter {
 public:
  std::string str() const { return out_.str(); }

  void BeginObject() { Open('{'); }
  void EndObject() { Close('}'); }
  void BeginArray() { Open('['); }
  void EndArray() { Close(']'); }
  void Key(const std::string& key) {
    Separate();
    Indent();
    out_ << Quote(key) << ": ";
    after_key_ = true;
  }
  void String(const std::string& s) { Value(Quote(s)); }
  void Number(double x) { Value(FormatNumber(x)); }
  void Int(long long n) { Value(std::to_string(n)); }
  void Bool(bool b) { Value(b ? "true" : "false"); }
  void NumberArray(const std::vector<double>& xs) {
    Separate();
    if (!after_key_) Indent();
    after_key_ = false;
    out_ << '[';
    for (std::size_t i = 0; i < xs.size(); ++i) out_ << (i ? ", " : "") << FormatNumber(xs[i]);
    out_ << ']';
    need_comma_ = true;
  }
  void NumberArray(const Eigen::VectorXd& x) {
    NumberArray(std::vector<double>(x.data(), x.data() + x.size()));
  }

  static std::string Quote(const std::string& s) { return JsonQuote(s); }

  static std::string FormatNumber(double x) {
    if (!std::isfinite(x)) return "null";
    // The shortest of %.15g, %.16g, %.17g that reads back exactly.
    char buffer[32];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(buffer, sizeof(buffer), "%.*g", digits, x);
      if (std::strtod(buffer, nullptr) == x) break;
    }
    return buffer;
  }

 private:
  void Open(char bracket) {
    Separate();
    if (!after_key_ && depth_ > 0) Indent();
    after_key_ = false;
    out_ << bracket;
    ++depth_;
    need_comma_ = false;
    empty_ = true;
  }
  void Close(char bracket) {
    --depth_;
    if (!empty_) {
      out_ << '\n';
      Indent();
    }
    out_ << bracket;
    need_comma_ = true;
    empty_ = false;
    if (depth_ == 0) out_ << '\n';
  }
  void Value(const std::string& text) {
    Separate();
    if (!after_key_) Indent();
    after_key_ = false;
    out_ << text;
    need_comma_ = true;
  }
  void Separate() {
    if (after_key_) return;
    if (need_comma_) out_ << ',';
    if (depth_ > 0) out_ << '\n';
    need_comma_ = false;
    empty_ = false;
  }
  void Indent() {
    for (int i = 0; i < depth_; ++i) out_ << "  ";
  }

  std::ostringstream out_;
  int depth_{0};
  bool need_comma_{false};
  bool after_key_{false};
  bool empty_{true};
};

}  // namespace idto::examples
