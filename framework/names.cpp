#include "kincal/framework/names.hpp"

#include <cstdio>

#include "kincal/framework/message_excerpt.hpp"

namespace kincal {

namespace {

// Length of the valid UTF-8 sequence at text[i] (1 for ASCII), 0 when it is not one, and its
// code point in `code`.
std::size_t utf8_sequence(const std::string& text, std::size_t i, unsigned& code) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i);
  std::size_t n = 0;
  unsigned min = 0;
  if (b < 0x80) {
    code = b;
    return 1;
  }
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2, min = 0x80, code = b & 0x1Fu;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3, min = 0x800, code = b & 0x0Fu;
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4, min = 0x10000, code = b & 0x07u;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0u) != 0x80u) return 0;
    code = (code << 6) | (byte(i + k) & 0x3Fu);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

}  // namespace

bool is_valid_utf8(const std::string& text) {
  unsigned code = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence(text, i, code);
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
    const std::size_t n = utf8_sequence(name, i, code);
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
