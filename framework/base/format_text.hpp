#pragma once
// printf-style formatting into a std::string, for the reports' aligned tables and figures.

#include <string>

namespace kincal {

/// `format` with its arguments, as std::snprintf writes them, whatever the length.
std::string format_text(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace kincal
