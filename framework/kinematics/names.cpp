#include "kincal/framework/kinematics/names.hpp"

#include <cstdio>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

bool is_valid_utf8(const std::string& text) {
  unsigned code = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence_length(text, i, &code);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

std::string name_problem(const std::string& name, NameKind kind) {
  if (name.empty()) return "is empty";
  const std::size_t max_bytes = kind == NameKind::kName ? kMaxNameBytes : kMaxColumnNameBytes;
  if (name.size() > max_bytes)
    return "is " + std::to_string(name.size()) + " bytes long, more than the " +
           std::to_string(max_bytes) + " allowed";
  unsigned code = 0;
  for (std::size_t i = 0; i < name.size();) {
    const std::size_t n = utf8_sequence_length(name, i, &code);
    if (n == 0) return "is not valid UTF-8";
    if (code < 0x20 || code == 0x7F || (code >= 0x80 && code < 0xA0)) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "U+%04X", code);
      return std::string("contains the control character ") + hex;
    }
    i += n;
  }
  if (std::string("=+-@").find(name[0]) != std::string::npos)
    return "starts with '" + name.substr(0, 1) +
           "', which makes a spreadsheet read the cell as a formula";
  const std::size_t bad = name.find_first_of(kind == NameKind::kName ? " ,;#\"'*?." : " ,;#\"'*?");
  if (bad != std::string::npos)
    return "contains '" + name.substr(bad, 1) +
           "' (names are measurement-file columns and parameter-name prefixes: no spaces, "
           "',', ';', '#', quotes, '*', '?' or '.')";
  return "";
}

}  // namespace kincal
