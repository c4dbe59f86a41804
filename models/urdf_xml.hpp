#pragma once
// The XML of a URDF at the level of its bytes, read the way TinyXML 2.6 (the parser urdfdom
// reads with) reads it. Two uses:
//   - refusing, before TinyXML sees a text, what would make it crash or misread: nesting
//     deeper than its recursion can take, more nodes than its memory should hold, a NUL
//     byte (TinyXML stops there), bytes that are not UTF-8 (TinyXML's UTF-8 reader skips the
//     bytes a lead byte announces, '<' included), an unterminated CDATA section or quoted
//     value (TinyXML then reads past the end of the text), a character reference whose ';'
//     lies behind markup (TinyXML's reference reader jumps over it);
//   - editing the user's own text in place: the export changes the values of a few
//     attributes and inserts elements, and every other byte stays as the user wrote it.
// The scanner follows TinyXML where a URDF that urdfdom reads could depend on it (what ends
// a comment, a declaration or an unknown node; which names and white space it takes) and is
// stricter where TinyXML is lenient about things a URDF has no use for (text outside the
// root element, a second root, a '<' that starts no markup): those are refused with the
// line. Everything kincal writes into XML goes through xml_comment_text or
// xml_attribute_text.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace kincal {

/// One sentence about a URDF kincal cannot take (the callers add the file).
class UrdfError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The limits on a URDF (docs/reliability.md, "Inputs"). The size is a model file's: the
/// model file `kincal model --urdf` writes keeps the whole text.
inline constexpr std::size_t kMaxUrdfBytes = std::size_t{16} << 20;
/// Elements inside one another (a URDF needs about six; TinyXML recurses once per level).
inline constexpr int kMaxUrdfDepth = 64;
/// Elements, text runs, comments, CDATA sections, declarations and other nodes: TinyXML and
/// urdfdom hold a few hundred bytes per node, so 16 MiB of "<a/>" would take gigabytes.
inline constexpr int kMaxUrdfNodes = 100000;
/// Attributes of one element (TinyXML looks each new one up among the earlier ones).
inline constexpr int kMaxUrdfAttributes = 256;

struct XmlAttribute {
  std::string name;
  std::string value;  ///< with entities and character references replaced, as TinyXML does
  std::size_t value_begin = 0, value_end = 0;  ///< the raw value's bytes (inside the quotes)
  char quote = 0;                              ///< '"', '\'' or 0 (unquoted)
};

struct XmlElement {
  std::string name;
  int parent = -1;              ///< index in XmlText::elements; -1 for the root
  std::size_t begin = 0;        ///< its '<'
  std::size_t tag_end = 0;      ///< just after its start tag ("/>" or ">")
  std::size_t end = 0;          ///< just after its end tag (tag_end when it is empty, <x/>)
  std::size_t close_begin = 0;  ///< the '<' of its end tag ('/' of "/>" when empty)
  bool empty = false;
  std::vector<XmlAttribute> attributes;

  const XmlAttribute* attribute(std::string_view attribute_name) const;
};

/// The elements of a document, in document order.
struct XmlText {
  std::vector<XmlElement> elements;
  int root = 0;
  /// Where a comment can go first: just after an XML declaration (<?xml ...?>), or after a
  /// byte order mark, or 0.
  std::size_t prolog_end = 0;

  /// The first child of element `parent` named `name` whose attribute `key` is `value` (any
  /// when `key` is empty); -1 when none.
  int child(int parent, std::string_view name, std::string_view key = {},
            std::string_view value = {}) const;
};

/// Reads `text` as above; throws UrdfError "line N: ..." on anything it refuses.
XmlText scan_urdf_xml(const std::string& text);

/// 1 + the number of line breaks before `offset`.
int line_at(const std::string& text, std::size_t offset);

/// `text` for an XML comment: control characters and bytes that are not UTF-8 written as
/// \xNN (docs/reliability.md, "Names": file names are the user's), and no "--" (a comment
/// ends at one) nor a final '-': "a--b" becomes "a- -b". A comment expands no entities, so
/// nothing else is escaped (an "&amp;" would show as such).
std::string xml_comment_text(const std::string& text);

/// `text` for an attribute value in double or single quotes: & < > " ' and tab, line feed and
/// carriage return (which a parser would turn into spaces) as references; the value reads
/// back exactly.
std::string xml_attribute_text(const std::string& text);

}  // namespace kincal
