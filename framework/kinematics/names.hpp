#pragma once
// One policy for the names a user gives (joints, actuators, sensors, readings): a name
// becomes a column of the measurement files kincal reads and writes, a cell of the CSVs it
// exports, a prefix of parameter names matched by --free patterns, and text on a terminal.
// What is accepted here therefore reads back through kincal's own readers, cannot start a
// spreadsheet formula, and cannot drive a terminal (docs/reliability.md, "Names").

#include <cstddef>
#include <string>

namespace kincal {

/// The longest name accepted, in bytes: far beyond any real joint name, far below the
/// measurement reader's line limit (a header holds one name per column).
inline constexpr std::size_t kMaxNameBytes = 128;

/// A column is a name with a suffix ("tracker.x", "joint1.theta"): dots allowed, a little
/// longer.
inline constexpr std::size_t kMaxColumnNameBytes = kMaxNameBytes + 32;
enum class NameKind { kName, kColumn };

/// Empty when `name` is acceptable; otherwise what is wrong with it, e.g. "contains the
/// control character \x1B". A name is 1 to kMaxNameBytes bytes of valid UTF-8 without
/// control characters, without the characters that separate or quote fields or make
/// patterns (space, ',', ';', '#', '"', '\'', '*', '?', '.'), and does not start with a
/// character that makes a spreadsheet cell a formula ('=', '+', '-', '@'). A kColumn may
/// hold dots and be up to kMaxColumnNameBytes long.
std::string name_problem(const std::string& name, NameKind kind = NameKind::kName);

/// The longest one-line text accepted where a name is not enough (a type's or preset's
/// description, a constraint's label), in bytes.
inline constexpr std::size_t kMaxTextBytes = 1000;

/// Empty when `text` is acceptable as one line of text shown on a terminal and in reports
/// (a description, a label): 1 to kMaxTextBytes bytes of valid UTF-8 without control
/// characters (no line break, escape or bell). Spaces and punctuation are fine.
std::string text_problem(const std::string& text);

/// Whether `text` is valid UTF-8 (what JSON can hold as a string).
bool is_valid_utf8(const std::string& text);

}  // namespace kincal
