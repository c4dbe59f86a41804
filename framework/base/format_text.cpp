#include "kincal/framework/base/format_text.hpp"

#include <cstdarg>
#include <cstdio>
#include <vector>

namespace kincal {

std::string format_text(const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string text;
  if (n > 0) {
    std::vector<char> buffer(static_cast<std::size_t>(n) + 1);
    std::vsnprintf(buffer.data(), buffer.size(), format, again);
    text.assign(buffer.data(), static_cast<std::size_t>(n));
  }
  va_end(again);
  return text;
}

}  // namespace kincal
