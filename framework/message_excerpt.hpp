#pragma once
// Quoting user input in an error message: whatever a file holds (a NUL byte, a 60 KB field,
// a line break, bytes that are not UTF-8), the message stays one short readable line.

#include <cstddef>
#include <string>

namespace kincal {

/// `text` with control characters and bytes outside valid UTF-8 written as \xNN, cut with
/// "..." once `max_chars` characters of the result are shown (an escape counts as its four).
/// Never contains a line break.
std::string message_excerpt(const std::string& text, std::size_t max_chars = 60);

}  // namespace kincal
