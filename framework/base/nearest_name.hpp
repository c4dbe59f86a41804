#pragma once
// "Did you mean": the known name nearest a misspelt one, for messages about an unknown
// command, option or name (`kincal calibrat`, `--seeed`).

#include <string>
#include <vector>

namespace kincal {

/// The optimal-string-alignment distance between a and b: insertions, deletions,
/// substitutions and swaps of two neighbouring characters, each 1.
int edit_distance(const std::string& a, const std::string& b);

/// The name of `known` nearest `given` when it is near enough to be a misspelling (at most 1
/// edit for names of up to 4 characters, 2 up to 8, 3 beyond; or `given` a prefix of exactly
/// one known name of at least 3 characters), the first of equals; "" otherwise.
std::string nearest_name(const std::string& given, const std::vector<std::string>& known);

}  // namespace kincal
