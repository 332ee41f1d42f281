#pragma once

/// @file
/// CSV fields as RFC 4180 writes them, for every CSV idto writes (joint and body names may
/// hold commas or quotes).

#include <string>

namespace idto {

/// `text` as one CSV field: unchanged unless it holds a comma, a double quote, a CR or an LF;
/// then enclosed in double quotes with every inner double quote doubled.
inline std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

}  // namespace idto
