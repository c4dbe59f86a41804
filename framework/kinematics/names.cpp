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

namespace {

// What is wrong with `text` as printable text of 1 to `max_bytes` bytes, or "".
std::string printable_problem(const std::string& text, std::size_t max_bytes) {
  if (text.empty()) return "is empty";
  if (text.size() > max_bytes)
    return "is " + std::to_string(text.size()) + " bytes long, more than the " +
           std::to_string(max_bytes) + " allowed";
  unsigned code = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence_length(text, i, &code);
    if (n == 0) return "is not valid UTF-8";
    if (code < 0x20 || code == 0x7F || (code >= 0x80 && code < 0xA0)) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "U+%04X", code);
      return std::string("contains the control character ") + hex;
    }
    i += n;
  }
  return "";
}

}  // namespace

std::string text_problem(const std::string& text) { return printable_problem(text, kMaxTextBytes); }

std::string name_problem(const std::string& name, NameKind kind) {
  const std::string problem =
      printable_problem(name, kind == NameKind::kName ? kMaxNameBytes : kMaxColumnNameBytes);
  if (!problem.empty()) return problem;
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
