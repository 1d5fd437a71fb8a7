#pragma once
// One field of a CSV line (RFC 4180): as it is, or, when it holds a comma, a double quote
// or a line break, in double quotes with its quotes doubled. The evaluators' labels come
// from file and folder names, which may hold any of them; unquoted, a comma in a model's
// folder shifted every later column of its rows.
#include <string>

namespace nns::report {

inline std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace nns::report
