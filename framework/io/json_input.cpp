#include "kincal/framework/io/json_input.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <vector>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

// nlohmann's what() starts with "[json.exception.parse_error.101] "; the reader needs only
// the rest ("parse error at line 3, column 5: ...").
std::string without_json_tag(const std::string& what) {
  const auto pos = what.find("] ");
  return pos == std::string::npos ? what : what.substr(pos + 2);
}

// A pointer into the text that tells the handler below how far the parser has read: the
// position of a duplicate key or of a too-deep bracket, which nlohmann's SAX events do not
// carry.
class TrackedChar {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackedChar(const char* p, const char** cursor) : p_(p), cursor_(cursor) {}
  reference operator*() const { return *p_; }
  TrackedChar& operator++() {
    *cursor_ = ++p_;
    return *this;
  }
  TrackedChar operator++(int) {
    TrackedChar old = *this;
    ++*this;
    return old;
  }
  bool operator==(const TrackedChar& other) const { return p_ == other.p_; }
  bool operator!=(const TrackedChar& other) const { return p_ != other.p_; }

 private:
  const char* p_;
  const char** cursor_;
};

// Builds the value like nlohmann's own DOM parser, and stops at a repeated key or at a
// nesting deeper than the limit. Errors are kept, not thrown through the parser.
class CheckedDomBuilder {
 public:
  CheckedDomBuilder(const std::string& text, const char** cursor, int max_depth)
      : text_(text), cursor_(cursor), max_depth_(max_depth) {}

  bool null() { return value(nullptr); }
  bool boolean(bool v) { return value(v); }
  bool number_integer(Json::number_integer_t v) { return value(v); }
  bool number_unsigned(Json::number_unsigned_t v) { return value(v); }
  bool number_float(Json::number_float_t v, const Json::string_t&) { return value(v); }
  bool string(Json::string_t& v) { return value(std::move(v)); }
  bool binary(Json::binary_t& v) { return value(Json::binary(std::move(v))); }

  bool start_object(std::size_t) { return open(Json::object()); }
  bool start_array(std::size_t) { return open(Json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(Json::string_t& k) {
    Frame& frame = frames_.back();
    if (!frame.keys.insert(k).second) {
      error_ = "line " + here() + ": key '" + message_excerpt(k) + "' appears twice in " + where() +
               "; expected each key once (the second would silently replace the first)";
      return false;
    }
    frame.key = k;
    element_ = &(*frame.value)[k];
    return true;
  }

  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) {
    // A number beyond double range is nlohmann's out_of_range.406, not a syntax error.
    error_ = (e.id == 406 ? "unreadable JSON: " : "malformed JSON: ") +
             message_excerpt(without_json_tag(e.what()), 300);
    return false;
  }

  const std::string& error() const { return error_; }
  Json& root() { return root_; }

 private:
  struct Frame {
    Json* value;
    std::set<std::string> keys;  // objects: the keys seen so far
    std::string key;             // objects: the current key
    std::size_t index = 0;       // arrays: elements so far
  };

  template <class Value>
  Json* place(Value&& v) {
    if (frames_.empty()) {
      root_ = Json(std::forward<Value>(v));
      return &root_;
    }
    Frame& frame = frames_.back();
    if (frame.value->is_array()) {
      frame.value->emplace_back(std::forward<Value>(v));
      ++frame.index;
      return &frame.value->back();
    }
    *element_ = Json(std::forward<Value>(v));
    return element_;
  }

  template <class Value>
  bool value(Value&& v) {
    place(std::forward<Value>(v));
    return true;
  }

  bool open(Json&& empty) {
    if (static_cast<int>(frames_.size()) >= max_depth_) {
      error_ = "line " + here() + ": nesting deeper than " + std::to_string(max_depth_) +
               " levels of objects and arrays; expected at most " + std::to_string(max_depth_);
      return false;
    }
    Json* placed = place(std::move(empty));
    frames_.push_back({placed, {}, {}, 0});
    return true;
  }

  bool close() {
    frames_.pop_back();
    return true;
  }

  // "line L, column C" of the character the parser read last.
  std::string here() const {
    const std::size_t offset = static_cast<std::size_t>(*cursor_ - text_.data());
    std::size_t line = 1, column = 0;
    for (std::size_t i = 0; i < offset && i < text_.size(); ++i) {
      if (text_[i] == '\n') {
        ++line;
        column = 0;
      } else {
        ++column;
      }
    }
    return std::to_string(line) + ", column " + std::to_string(column);
  }

  // The open object, as a path: "the top-level object", "mechanism.legs[2]".
  std::string where() const {
    if (frames_.size() <= 1) return "the top-level object";
    std::vector<std::string> steps;
    for (std::size_t f = 0; f + 1 < frames_.size(); ++f) {
      const Frame& frame = frames_[f];
      if (frame.value->is_array())
        steps.push_back("[" + std::to_string(frame.index - 1) + "]");
      else
        steps.push_back((steps.empty() ? "" : ".") + message_excerpt(frame.key));
    }
    // Each key is cut to 60 characters, but 64 levels of them would still make a long line:
    // beyond kMaxPath characters, the first step, "..." and the innermost steps that fit.
    constexpr std::size_t kMaxPath = 200;
    std::string path;
    for (const std::string& step : steps) path += step;
    if (path.size() <= kMaxPath) return "object " + path;
    std::string tail = steps.back();
    for (std::size_t i = steps.size() - 1;
         i-- > 1 && tail.size() + steps[i].size() <= kMaxPath - 80;)
      tail.insert(0, steps[i]);
    path = steps.front() + "..." + tail;
    return "object " + path;
  }

  const std::string& text_;
  const char** cursor_;
  int max_depth_;
  Json root_;
  std::vector<Frame> frames_;
  Json* element_ = nullptr;
  std::string error_;
};

std::string mebibytes(std::size_t bytes) {
  return std::to_string(bytes >> 20) + " MiB (" + std::to_string(bytes) + " bytes)";
}

}  // namespace

Json parse_json_text(const std::string& text, const std::string& source, const JsonLimits& limits) {
  if (text.size() > limits.max_bytes)
    throw std::invalid_argument(source + ": larger than the limit of " +
                                mebibytes(limits.max_bytes) + " for a JSON file");
  const char* cursor = text.data();
  CheckedDomBuilder builder(text, &cursor, limits.max_depth);
  const char* begin = text.data();
  const bool ok = Json::sax_parse(TrackedChar(begin, &cursor),
                                  TrackedChar(begin + text.size(), &cursor), &builder);
  if (!ok) throw std::invalid_argument(source + ": " + builder.error());
  return std::move(builder.root());
}

std::string read_file_text(const std::string& path, const std::string& kind,
                           std::size_t max_bytes) {
  // An ifstream opens a directory fine and fails only on the first read, with a message
  // that does not name the file.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw std::invalid_argument(path + ": is a directory, expected a " + kind);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open " + kind + " (missing or unreadable)");
  // Read at most one byte past the limit: a device such as /dev/zero never ends.
  std::string text;
  std::vector<char> chunk(1 << 16);
  while (text.size() <= max_bytes && in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw std::invalid_argument(path + ": cannot read " + kind + " (read error)");
  if (text.size() > max_bytes)
    throw std::invalid_argument(path + ": larger than the limit of " + mebibytes(max_bytes) +
                                " for a " + kind);
  return text;
}

Json read_json_file(const std::string& path, const std::string& kind, const JsonLimits& limits) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw std::invalid_argument(path + ": is a directory, expected a " + kind + " (JSON)");
  return parse_json_text(read_file_text(path, kind, limits.max_bytes), path, limits);
}

std::string json_excerpt(const Json& value, std::size_t max_chars) {
  // Values come from a parsed file, so their strings are valid UTF-8 and dump() cannot
  // throw; replace anyway rather than throw while building an error message.
  return message_excerpt(value.dump(-1, ' ', false, Json::error_handler_t::replace), max_chars);
}

}  // namespace kincal
