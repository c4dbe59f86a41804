#pragma once
// Reading JSON that a user wrote: size and nesting limits, duplicate keys rejected, and
// one-line messages that name the file and the place. nlohmann's own parse accepts a
// repeated key (the last one wins, so a second "free" silently replaces the first) and
// nests as deep as memory allows (the recursive dump() of such a value overflows the stack).

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace kincal {

struct JsonLimits {
  /// Objects and arrays inside one another; a kincal file needs fewer than ten.
  int max_depth = 64;
  /// Size of the whole text in bytes.
  std::size_t max_bytes = std::size_t{16} << 20;
};

/// Parses `text` as one JSON value. Throws std::invalid_argument with one line starting with
/// "<source>: ": "malformed JSON: parse error at line L, column C: ...", "unreadable JSON:
/// number overflow ...", "line L, column C: key 'k' appears twice in <where>; ...", "line L,
/// column C: nesting deeper than N levels ...", or the size limit.
nlohmann::ordered_json parse_json_text(const std::string& text, const std::string& source,
                                       const JsonLimits& limits = {});

/// The bytes of file `path`, at most `max_bytes` (reading stops one byte past it, so a
/// device such as /dev/zero fails at once). Throws std::invalid_argument "<path>: is a
/// directory, expected a <kind>", "<path>: cannot open <kind> (missing or unreadable)" or
/// "<path>: larger than the limit of N MiB for a <kind>".
std::string read_file_text(const std::string& path, const std::string& kind, std::size_t max_bytes);

/// Reads the file `path` and parses it as parse_json_text does; `kind` names what the file
/// should be in messages (e.g. "model file"): "<path>: is a directory, expected a model file
/// (JSON)", "<path>: cannot open model file (missing or unreadable)".
nlohmann::ordered_json read_json_file(const std::string& path, const std::string& kind,
                                      const JsonLimits& limits = {});

/// `value` as compact JSON for an error message, cut to at most about `max_chars` characters
/// ("[1,2,3,4,..."), so that a message stays one readable line whatever the file holds.
std::string json_excerpt(const nlohmann::ordered_json& value, std::size_t max_chars = 60);

}  // namespace kincal
