// A CSV field as RFC 4180 writes it: quoted when it holds a comma, a quote
// or a line break (the sweep's rows and the evaluation's).
#pragma once

#include <string>

namespace nearcap::analysis {

inline std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace nearcap::analysis
