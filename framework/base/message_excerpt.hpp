#pragma once
// Quoting user input in an error message: whatever a file holds (a NUL byte, a 60 KB field,
// a line break, bytes that are not UTF-8), the message stays one short readable line.

#include <cstddef>
#include <string>

namespace kincal {

/// Length of the valid UTF-8 sequence at text[i] (1 for ASCII), or 0 when none starts there
/// (overlong forms, surrogates and code points beyond U+10FFFF are not valid); its code point
/// in `*code` when given.
std::size_t utf8_sequence_length(const std::string& text, std::size_t i, unsigned* code = nullptr);

/// `text` with control characters and bytes outside valid UTF-8 written as \xNN, cut with
/// "..." once `max_chars` characters of the result are shown (an escape counts as its four).
/// Never contains a line break.
std::string message_excerpt(const std::string& text, std::size_t max_chars = 60);

/// `text` whole, with control characters and bytes outside valid UTF-8 written as \xNN: a
/// file name or other user text that is safe on a terminal (no escape sequences, no bell)
/// and stays on one line of a report or a comment line of a file.
inline std::string printable(const std::string& text) {
  return message_excerpt(text, static_cast<std::size_t>(-1));
}

}  // namespace kincal
