#include "kincal/models/urdf_xml.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <set>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

namespace {

// TinyXML's classes of bytes (C locale): white space is isspace(); a name starts with a
// letter, '_' or any byte from 127 up and goes on with those, digits, '-', '.' and ':'.
bool is_space(unsigned char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }
bool is_name_start(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c >= 127;
}
bool is_name_char(unsigned char c) {
  return is_name_start(c) || (c >= '0' && c <= '9') || c == '-' || c == '.' || c == ':';
}

void append_utf8(std::string& out, unsigned long code) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xC0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  }
}

class Scanner {
 public:
  explicit Scanner(const std::string& text) : s_(text), n_(text.size()) {}

  XmlText run() {
    const std::size_t nul = s_.find('\0');
    if (nul != std::string::npos) fail(nul, "a NUL byte, which no XML text holds");
    if (starts(0, "\xEF\xBB\xBF")) out_.prolog_end = 3;
    bool first = true;
    for (;;) {
      if (open_.empty()) {
        skip_space();
        if (p_ >= n_) break;
        if (s_[p_] != '<')
          fail(p_, std::string("text ") + (seen_root_ ? "after the end of" : "before") +
                       " the root element <robot>");
        if (starts(p_, "</")) fail(p_, "an end tag with no start tag");
        if (starts(p_, "<![CDATA[")) fail(p_, "a CDATA section outside the root element");
        const bool declaration = starts_nocase(p_, "<?xml");
        markup();
        // A comment goes after an XML declaration proper (not <?xml-stylesheet?>), which
        // must stay first.
        if (first && declaration && !is_name_char(static_cast<unsigned char>(s_[begin_ + 5])))
          out_.prolog_end = p_;
        first = false;
        continue;
      }
      const XmlElement& e = out_.elements[static_cast<std::size_t>(open_.back())];
      skip_space();
      if (p_ >= n_)
        fail(e.begin, "<" + excerpt(e.name) + "> is not closed (no </" + excerpt(e.name) + ">)");
      if (s_[p_] != '<')
        text();
      else if (starts(p_, "</"))
        end_tag();
      else
        markup();
    }
    if (!seen_root_) fail(n_, "no root element (a URDF is one <robot> element)");
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw UrdfError("line " + std::to_string(line_at(s_, std::min(at, n_))) + ": " + what);
  }
  static std::string excerpt(const std::string& text) { return message_excerpt(text, 40); }

  bool starts(std::size_t at, const char* literal) const {
    const std::size_t len = std::strlen(literal);
    return at + len <= n_ && s_.compare(at, len, literal) == 0;
  }
  bool starts_nocase(std::size_t at, const char* literal) const {
    const std::size_t len = std::strlen(literal);
    if (at + len > n_) return false;
    for (std::size_t i = 0; i < len; ++i)
      if (std::tolower(static_cast<unsigned char>(s_[at + i])) != literal[i]) return false;
    return true;
  }

  // TinyXML's SkipWhiteSpace (UTF-8): isspace() and the three-byte sequences of U+FEFF,
  // U+FFFE and U+FFFF.
  void skip_space(std::size_t& at) const {
    while (at < n_) {
      if (starts(at, "\xEF\xBB\xBF") || starts(at, "\xEF\xBF\xBE") || starts(at, "\xEF\xBF\xBF"))
        at += 3;
      else if (is_space(static_cast<unsigned char>(s_[at])))
        ++at;
      else
        break;
    }
  }
  void skip_space() { skip_space(p_); }

  void count_node(std::size_t at) {
    if (++nodes_ > kMaxUrdfNodes)
      fail(at, "more than " + std::to_string(kMaxUrdfNodes) +
                   " XML nodes (elements, comments, texts); a robot's URDF has a few thousand");
  }

  // Bytes [from, to) must be UTF-8: kincal keeps the URDF's text in a model file (JSON).
  void check_utf8(std::size_t from, std::size_t to, const std::string& where) const {
    for (std::size_t i = from; i < to;) {
      const std::size_t len = utf8_sequence_length(s_, i);
      if (len == 0 || i + len > to) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(s_[i]));
        fail(i, where + " is not valid UTF-8 (byte " + hex +
                    "); kincal reads a URDF as UTF-8 and keeps its text in the model file: "
                    "save the file as UTF-8");
      }
      i += len;
    }
  }

  // An '&' at `at` in text or a quoted value, as TinyXML's GetEntity reads it, appended to
  // `value` (a named entity or a character reference; nothing for another '&', which TinyXML
  // drops); returns the position after it. TinyXML looks for a character reference's ';'
  // anywhere further on, so "&#x" jumps over whatever lies before the next ';', markup
  // included: only the well-formed references &#DDD; and &#xHHH; (a lowercase x, as TinyXML
  // reads) are accepted.
  std::size_t entity(std::size_t at, std::string* value) const {
    if (at + 1 < n_ && s_[at + 1] == '#') {
      const bool hex = at + 2 < n_ && s_[at + 2] == 'x';
      std::size_t q = at + (hex ? 3 : 2);
      const std::size_t digits = q;
      unsigned long code = 0;
      bool too_large = false;
      for (; q < n_; ++q) {
        const char c = s_[q];
        int d = -1;
        if (c >= '0' && c <= '9')
          d = c - '0';
        else if (hex && c >= 'a' && c <= 'f')
          d = c - 'a' + 10;
        else if (hex && c >= 'A' && c <= 'F')
          d = c - 'A' + 10;
        if (d < 0) break;
        code = code * (hex ? 16 : 10) + static_cast<unsigned long>(d);
        if (code > 0x10FFFF) too_large = true, code = 0x110000;
      }
      if (q == digits || q >= n_ || s_[q] != ';')
        fail(at, "a malformed character reference '" +
                     excerpt(s_.substr(at, std::min<std::size_t>(12, n_ - at))) +
                     "' (expected &#DDD; or &#xHHH;; write &amp; for a '&')");
      // U+0000 would end the value urdfdom gets (a C string) where kincal's does not.
      if (code == 0 || too_large || (code >= 0xD800 && code <= 0xDFFF))
        fail(at, "the character reference '" + excerpt(s_.substr(at, q + 1 - at)) +
                     "' is not a character XML allows");
      if (value) append_utf8(*value, code);
      return q + 1;
    }
    static const struct {
      const char* text;
      char c;
    } kNamed[] = {{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    for (const auto& named : kNamed)
      if (starts(at, named.text)) {
        if (value) *value += named.c;
        return at + std::strlen(named.text);
      }
    return at + 1;  // TinyXML drops the '&' of an unknown entity (length 0) and reads on
  }

  // Character data up to the next '<' inside element `open_.back()`.
  void text() {
    count_node(p_);
    const std::size_t from = p_;
    while (p_ < n_ && s_[p_] != '<') p_ = s_[p_] == '&' ? entity(p_, nullptr) : p_ + 1;
    const XmlElement& e = out_.elements[static_cast<std::size_t>(open_.back())];
    if (p_ >= n_) fail(e.begin, "<" + excerpt(e.name) + "> is not closed");
    check_utf8(from, p_, "the text in <" + excerpt(e.name) + ">");
  }

  // A node that starts with '<' and is not an end tag, as TinyXML's Identify tells them.
  void markup() {
    begin_ = p_;
    count_node(p_);
    if (starts_nocase(p_, "<?xml")) {
      declaration();
    } else if (starts(p_, "<!--")) {
      delimited("<!--", "-->", "a comment");
    } else if (starts(p_, "<![CDATA[")) {
      delimited("<![CDATA[", "]]>", "a CDATA section");
    } else if (starts(p_, "<!") || starts(p_, "<?")) {
      // TinyXML's unknown node (a DOCTYPE, a processing instruction): up to the first '>'.
      const std::size_t close = s_.find('>', p_);
      if (close == std::string::npos)
        fail(p_, "'" + excerpt(s_.substr(p_, 20)) + "' is not closed");
      const std::string inside = s_.substr(p_, close - p_);
      if (starts(p_, "<!DOCTYPE") && std::count(inside.begin(), inside.end(), '[') >
                                         std::count(inside.begin(), inside.end(), ']'))
        fail(p_,
             "a DOCTYPE with an internal subset ([...]), which TinyXML, the parser urdfdom "
             "reads with, cannot read");
      check_utf8(p_, close, starts(p_, "<?") ? "a processing instruction" : "a DOCTYPE");
      p_ = close + 1;
    } else if (p_ + 1 < n_ && is_name_start(static_cast<unsigned char>(s_[p_ + 1]))) {
      start_tag();
    } else {
      fail(p_,
           "a '<' that starts no element, comment or declaration (write &lt; for a '<' "
           "in text)");
    }
  }

  void delimited(const char* open, const char* close, const char* what) {
    const std::size_t end = s_.find(close, p_ + std::strlen(open));
    if (end == std::string::npos) fail(p_, std::string(what) + " is not closed (no " + close + ")");
    check_utf8(p_, end, what);
    p_ = end + std::strlen(close);
  }

  // <?xml ...>, read as TinyXML's TiXmlDeclaration::Parse reads it: version, encoding and
  // standalone as attributes, anything else skipped up to white space or '>', the first
  // '>' outside those attributes' values ending it.
  void declaration() {
    std::size_t q = p_ + 5;
    for (;;) {
      if (q >= n_) fail(p_, "the XML declaration is not closed");
      if (s_[q] == '>') break;
      skip_space(q);
      if (q >= n_) fail(p_, "the XML declaration is not closed");
      if (starts_nocase(q, "version") || starts_nocase(q, "encoding") ||
          starts_nocase(q, "standalone")) {
        XmlAttribute ignored;
        q = attribute(q, "the XML declaration", ignored);
      } else {
        while (q < n_ && s_[q] != '>' && !is_space(static_cast<unsigned char>(s_[q]))) ++q;
      }
    }
    check_utf8(p_, q, "the XML declaration");
    p_ = q + 1;
  }

  // name = value, as TiXmlAttribute::Parse reads it; returns the position after it.
  std::size_t attribute(std::size_t q, const std::string& where, XmlAttribute& a) const {
    const std::size_t name_begin = q;
    if (q >= n_ || !is_name_start(static_cast<unsigned char>(s_[q])))
      fail(q, "expected an attribute name in " + where);
    while (q < n_ && is_name_char(static_cast<unsigned char>(s_[q]))) ++q;
    a.name = s_.substr(name_begin, q - name_begin);
    check_utf8(name_begin, q, "an attribute name in " + where);
    skip_space(q);
    if (q >= n_ || s_[q] != '=')
      fail(q, "expected '=' after attribute '" + excerpt(a.name) + "' in " + where);
    skip_space(++q);
    if (q >= n_) fail(q, "attribute '" + excerpt(a.name) + "' in " + where + " has no value");
    const std::string what = "the value of attribute '" + excerpt(a.name) + "' in " + where;
    if (s_[q] == '"' || s_[q] == '\'') {
      a.quote = s_[q];
      a.value_begin = ++q;
      while (q < n_ && s_[q] != a.quote) {
        if (s_[q] == '&')
          q = entity(q, &a.value);
        else
          a.value += s_[q++];
      }
      if (q >= n_) fail(a.value_begin - 1, what + " is not closed (no " + a.quote + ")");
      a.value_end = q++;
    } else {
      // TinyXML takes an unquoted value up to white space, '/' or '>', as it is.
      a.value_begin = q;
      while (q < n_ && !is_space(static_cast<unsigned char>(s_[q])) && s_[q] != '/' &&
             s_[q] != '>') {
        if (s_[q] == '"' || s_[q] == '\'')
          fail(q, what + " has a quote but does not start with one");
        a.value += s_[q++];
      }
      a.value_end = q;
    }
    check_utf8(a.value_begin, a.value_end, what);
    return q;
  }

  void start_tag() {
    XmlElement e;
    e.begin = p_;
    // TinyXML skips white space between '<' and the name: here only U+FEFF, U+FFFE or U+FFFF
    // can be there (its bytes count as letters), and a name must follow them.
    std::size_t q = p_ + 1;
    skip_space(q);
    const std::size_t name_begin = q;
    if (q >= n_ || !is_name_start(static_cast<unsigned char>(s_[q])))
      fail(p_, "a '<' that starts no element, comment or declaration");
    while (q < n_ && is_name_char(static_cast<unsigned char>(s_[q]))) ++q;
    e.name = s_.substr(name_begin, q - name_begin);
    check_utf8(name_begin, q, "an element name");
    const std::string where = "<" + excerpt(e.name) + ">";
    if (open_.empty()) {
      if (seen_root_)
        fail(p_, "a second root element " + where + " (a URDF is one <robot> element)");
      seen_root_ = true;
      out_.root = static_cast<int>(out_.elements.size());
    } else {
      e.parent = open_.back();
    }
    if (static_cast<int>(open_.size()) + 1 > kMaxUrdfDepth)
      fail(p_, "elements nested more than " + std::to_string(kMaxUrdfDepth) + " deep (" + where +
                   "); a URDF needs about six levels");
    std::set<std::string> names;
    for (;;) {
      skip_space(q);
      if (q >= n_) fail(e.begin, "the start tag of " + where + " is not closed");
      if (s_[q] == '/') {
        if (q + 1 >= n_ || s_[q + 1] != '>') fail(q, "'/' not followed by '>' in " + where);
        e.empty = true;
        e.close_begin = q;
        q += 2;
        break;
      }
      if (s_[q] == '>') {
        ++q;
        break;
      }
      XmlAttribute a;
      q = attribute(q, where, a);
      if (!names.insert(a.name).second)
        fail(a.value_begin, where + " has attribute '" + excerpt(a.name) + "' twice");
      if (names.size() > static_cast<std::size_t>(kMaxUrdfAttributes))
        fail(a.value_begin,
             where + " has more than " + std::to_string(kMaxUrdfAttributes) + " attributes");
      e.attributes.push_back(std::move(a));
    }
    e.tag_end = q;
    if (e.empty) e.end = q;
    p_ = q;
    out_.elements.push_back(std::move(e));
    if (!out_.elements.back().empty) open_.push_back(static_cast<int>(out_.elements.size()) - 1);
  }

  // "</name" white space ">" closing the innermost open element, as TinyXML matches it.
  void end_tag() {
    XmlElement& e = out_.elements[static_cast<std::size_t>(open_.back())];
    std::size_t q = p_ + 2;
    if (!(q + e.name.size() <= n_ && s_.compare(q, e.name.size(), e.name) == 0))
      fail(p_, "'" + excerpt(s_.substr(p_, std::min<std::size_t>(n_ - p_, 30))) + "' where </" +
                   excerpt(e.name) + "> should close <" + excerpt(e.name) + "> of line " +
                   std::to_string(line_at(s_, e.begin)));
    q += e.name.size();
    skip_space(q);
    if (q >= n_ || s_[q] != '>')
      fail(p_, "the end tag </" + excerpt(e.name) + "> is not closed with '>'");
    e.close_begin = p_;
    e.end = q + 1;
    p_ = q + 1;
    open_.pop_back();
  }

  const std::string& s_;
  const std::size_t n_;
  std::size_t p_ = 0, begin_ = 0;
  int nodes_ = 0;
  bool seen_root_ = false;
  std::vector<int> open_;
  XmlText out_;
};

}  // namespace

const XmlAttribute* XmlElement::attribute(std::string_view attribute_name) const {
  for (const XmlAttribute& a : attributes)
    if (a.name == attribute_name) return &a;
  return nullptr;
}

int XmlText::child(int parent, std::string_view name, std::string_view key,
                   std::string_view value) const {
  // Children follow their parent in document order.
  for (std::size_t i = static_cast<std::size_t>(parent) + 1; i < elements.size(); ++i) {
    const XmlElement& e = elements[i];
    if (e.begin >= elements[static_cast<std::size_t>(parent)].end) break;
    if (e.parent != parent || e.name != name) continue;
    if (key.empty()) return static_cast<int>(i);
    const XmlAttribute* a = e.attribute(key);
    if (a && a->value == value) return static_cast<int>(i);
  }
  return -1;
}

XmlText scan_urdf_xml(const std::string& text) { return Scanner(text).run(); }

int line_at(const std::string& text, std::size_t offset) {
  const auto end = text.begin() + static_cast<std::ptrdiff_t>(std::min(offset, text.size()));
  return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
}

std::string xml_comment_text(const std::string& text) {
  std::string out = printable(text);
  for (std::size_t at = out.find("--"); at != std::string::npos; at = out.find("--", at))
    out.insert(at + 1, " ");
  if (!out.empty() && out.back() == '-') out += ' ';
  return out;
}

std::string xml_attribute_text(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      case '\t':
        out += "&#9;";
        break;
      case '\n':
        out += "&#10;";
        break;
      case '\r':
        out += "&#13;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace kincal
