#include "kincal/framework/base/message_excerpt.hpp"

#include <cstdio>

namespace kincal {

std::size_t utf8_sequence_length(const std::string& text, std::size_t i, unsigned* code) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i);
  unsigned value = 0, min = 0;
  std::size_t n = 0;
  if (b < 0x80) {
    n = 1, value = b;
  } else if (b >= 0xC2 && b <= 0xDF) {
    n = 2, min = 0x80, value = b & 0x1Fu;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3, min = 0x800, value = b & 0x0Fu;
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4, min = 0x10000, value = b & 0x07u;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0u) != 0x80u) return 0;
    value = (value << 6) | (byte(i + k) & 0x3Fu);
  }
  if (value < min || value > 0x10FFFF || (value >= 0xD800 && value <= 0xDFFF)) return 0;
  if (code) *code = value;
  return n;
}

std::string message_excerpt(const std::string& text, std::size_t max_chars) {
  std::string out;
  std::size_t shown = 0;
  for (std::size_t i = 0; i < text.size();) {
    if (shown >= max_chars) return out + "...";
    const unsigned char c = static_cast<unsigned char>(text[i]);
    unsigned code = 0;
    const std::size_t n = c >= 0x80 ? utf8_sequence_length(text, i, &code) : 0;
    if (c >= 0x20 && c < 0x7F) {
      out += text[i++];
      ++shown;
    } else if (n > 0 && code >= 0xA0) {  // a C1 control character (U+0080..U+009F) is escaped
      out.append(text, i, n);
      i += n;
      ++shown;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", c);
      out += hex;
      ++i;
      shown += 4;
    }
  }
  return out;
}

}  // namespace kincal
