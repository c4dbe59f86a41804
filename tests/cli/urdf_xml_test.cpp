// The URDF's XML as kincal scans it (cli/urdf_xml.hpp): the same elements, nesting and
// attribute values as TinyXML, the parser urdfdom reads with, on documents that use its
// leniencies and XML's corners; refusals, with the line, of what would crash TinyXML or make
// it read something else than it seems to; the escaping of what kincal writes into XML.

#include <gtest/gtest.h>
#include <tinyxml.h>

#include <string>
#include <utility>
#include <vector>

#include "kincal/models/urdf_xml.hpp"

namespace kincal::cli {
namespace {

struct Seen {
  std::string name;
  int depth = 0;
  std::vector<std::pair<std::string, std::string>> attributes;
  bool operator==(const Seen& o) const {
    return name == o.name && depth == o.depth && attributes == o.attributes;
  }
};

std::ostream& operator<<(std::ostream& os, const Seen& s) {
  os << std::string(static_cast<std::size_t>(s.depth), ' ') << "<" << s.name;
  for (const auto& [k, v] : s.attributes) os << " " << k << "=[" << v << "]";
  return os << ">";
}

// TinyXML's elements in document order, read as urdfdom has it read them (UTF-8).
std::vector<Seen> tinyxml_elements(const std::string& text, std::string* error) {
  TiXmlDocument doc;
  doc.Parse(("\xEF\xBB\xBF" + text).c_str());
  if (doc.Error()) {
    *error = doc.ErrorDesc();
    return {};
  }
  std::vector<Seen> out;
  std::vector<std::pair<const TiXmlNode*, int>> stack;
  for (const TiXmlNode* n = doc.LastChild(); n; n = n->PreviousSibling()) stack.push_back({n, 1});
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    const TiXmlElement* e = node->ToElement();
    if (!e) continue;
    Seen seen{e->ValueStr(), depth, {}};
    for (const TiXmlAttribute* a = e->FirstAttribute(); a; a = a->Next())
      seen.attributes.emplace_back(a->Name(), a->Value());
    out.push_back(seen);
    for (const TiXmlNode* c = node->LastChild(); c; c = c->PreviousSibling())
      stack.push_back({c, depth + 1});
  }
  return out;
}

std::vector<Seen> scanned_elements(const XmlText& xml) {
  std::vector<Seen> out;
  for (const XmlElement& e : xml.elements) {
    Seen seen{e.name, 1, {}};
    for (int p = e.parent; p >= 0; p = xml.elements[static_cast<std::size_t>(p)].parent)
      ++seen.depth;
    for (const XmlAttribute& a : e.attributes) seen.attributes.emplace_back(a.name, a.value);
    out.push_back(seen);
  }
  return out;
}

TEST(UrdfXml, ReadsWhatTinyXmlReads) {
  const std::vector<std::string> documents = {
      // Declarations, a stylesheet (TinyXML takes any "<?xml" for a declaration), a DOCTYPE
      // without and with an empty internal subset, comments and CDATA holding markup.
      "<?xml version=\"1.0\" encoding='UTF-8' standalone=\"yes\"?>\n<?xml-stylesheet "
      "href=\"a.xsl\" type=\"text/xsl\"?>\n<!DOCTYPE robot SYSTEM \"urdf.dtd\">\n<!-- <joint "
      "name=\"c\"> -->\n<robot name=\"r\"><![CDATA[<origin xyz=\"1 2 3\"/>]]><link "
      "name=\"a\"/></robot>\n<!-- after -->",
      "<?XML version=\"1.0\"?><!DOCTYPE robot []><robot/>",
      "\xEF\xBB\xBF<robot name='x'><?pi <a> ?><a/></robot>",
      // TinyXML's leniencies: unquoted values, no white space between attributes, white
      // space in end tags, \v and \f, U+FEFF as white space, an empty unquoted value.
      "<robot name=r a=\"1\"b='2'><link name=l1 /><x y= ></x ><z\v\fa=\"\xEF\xBB\xBF\"\xEF\xBB\xBF"
      "b=\"c\"/></robot\t>",
      // Entities and references in values, unknown entities kept, names with . - : _ and
      // bytes from 127 up.
      "<robot name=\"caf&#xE9;&#233;&#x1F600;&amp;&lt;&gt;&quot;&apos;&foo;&\"><a.b-c:d "
      "_x=\"\n\t\"/>"
      "<\xC3\xA9l\xC3\xA9ment attr\xC3\xA9=\"\xE2\x82\xAC\"/></robot>",
      // U+FFFF between '<' and a name is white space to TinyXML (found by fuzz_urdf_file).
      "<robot><\xEF\xBF\xBFs a=\"1\"></s></robot>",
      // Text with references, markup characters and line breaks; a CR LF; nested elements.
      "<robot>\r\n  text &#60; &gt; ] ]]> \"'<a><b><c d=\"&#x3c;\"/></b></a>tail</robot>",
  };
  for (const std::string& text : documents) {
    std::string error;
    const std::vector<Seen> tiny = tinyxml_elements(text, &error);
    ASSERT_EQ(error, "") << text;
    const std::vector<Seen> scanned = scanned_elements(scan_urdf_xml(text));
    ASSERT_EQ(scanned.size(), tiny.size()) << text;
    for (std::size_t i = 0; i < tiny.size(); ++i) EXPECT_EQ(scanned[i], tiny[i]) << text;
  }
}

TEST(UrdfXml, RefusesWithTheLineWhatTinyXmlWouldMisreadOrCrashOn) {
  const std::string deep = "<robot>" + std::string(500, '\n') + [] {
    std::string s;
    for (int i = 0; i < 64; ++i) s += "<a>";
    for (int i = 0; i < 64; ++i) s += "</a>";
    return s;
  }() + "</robot>";
  std::string many = "<robot>";
  for (int i = 0; i < kMaxUrdfNodes; ++i) many += "<a/>";
  many += "</robot>";
  std::string attributes = "<robot";
  for (int i = 0; i <= kMaxUrdfAttributes; ++i) attributes += " a" + std::to_string(i) + "=\"\"";
  attributes += "/>";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"<robot>\n<![CDATA[ never closed </robot>", "line 2: a CDATA section is not closed"},
      {"<robot>\n<!-- never closed </robot>", "line 2: a comment is not closed"},
      // TinyXML looks for the reference's ';' further on: "&#x" would swallow the <a>.
      {"<robot>\n\n&#x<a name=\"b\"/>x;</robot>", "line 3: a malformed character reference"},
      {"<robot name=\"&#X41;\"/>", "line 1: a malformed character reference"},
      {"<robot name=\"&#xD800;\"/>", "is not a character XML allows"},
      {"<robot name=\"&#x110000;\"/>", "is not a character XML allows"},
      // urdfdom reads values as C strings: a NUL would end its name and not kincal's.
      {"<robot name=\"a&#0;b\"/>", "is not a character XML allows"},
      {"<robot name=\"a\n\nb", "line 1: the value of attribute 'name' in <robot> is not closed"},
      {std::string("<robot>\n\0</robot>", 18), "line 2: a NUL byte"},
      {"<robot>\n<joint name=\"j\xE9\"/></robot>",
       "line 2: the value of attribute 'name' in <joint> is not valid UTF-8 (byte \\xE9)"},
      {"<robot>\n<!-- \xC3( -->\n</robot>", "line 2: a comment is not valid UTF-8"},
      {"<robot>\n< joint/></robot>", "line 2: a '<' that starts no element"},
      {"<robot/>\n<robot/>", "line 2: a second root element <robot>"},
      {"<robot/>\ntext", "line 2: text after the end of the root element"},
      {"text<robot/>", "line 1: text before the root element"},
      {"<!DOCTYPE robot [\n<!ENTITY a \"b\">\n]><robot/>", "a DOCTYPE with an internal subset"},
      {deep, "line 501: elements nested more than 64 deep (<a>)"},
      {many, "more than 100000 XML nodes"},
      {attributes, "<robot> has more than 256 attributes"},
      {"<robot a=\"1\" a=\"2\"/>", "<robot> has attribute 'a' twice"},
      {"<robot>\n<a>\n</b></robot>",
       "line 3: '</b></robot>' where </a> should close <a> of line 2"},
      {"<robot>\n<a>", "line 2: <a> is not closed"},
      {"<robot a=b\"c\"/>", "has a quote but does not start with one"},
      {"<?xml version=\"1.0\"", "the XML declaration is not closed"},
      {"", "no root element"},
      {"</robot>", "an end tag with no start tag"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      scan_urdf_xml(text);
      ADD_FAILURE() << "accepted: " << text.substr(0, 200);
    } catch (const UrdfError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
          << e.what() << "\nexpected: " << expected;
    }
  }
  // 64 levels are fine.
  std::string nested = "<robot>";
  for (int i = 0; i < 63; ++i) nested += "<a>";
  for (int i = 0; i < 63; ++i) nested += "</a>";
  EXPECT_EQ(scan_urdf_xml(nested + "</robot>").elements.size(), 64u);
}

TEST(UrdfXml, KnowsWhereItsElementsAndValuesAre) {
  const std::string text =
      "\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<robot><joint name=\"j&amp;1\"><origin xyz='1 2 3' "
      "rpy=0/></joint><joint name=\"j2\"/></robot>";
  const XmlText xml = scan_urdf_xml(text);
  EXPECT_EQ(text.substr(0, xml.prolog_end), "\xEF\xBB\xBF<?xml version=\"1.0\"?>");
  const int joint = xml.child(xml.root, "joint", "name", "j&1");
  ASSERT_GE(joint, 0);
  const int origin = xml.child(joint, "origin");
  ASSERT_GE(origin, 0);
  const XmlElement& o = xml.elements[static_cast<std::size_t>(origin)];
  EXPECT_EQ(text.substr(o.begin, o.end - o.begin), "<origin xyz='1 2 3' rpy=0/>");
  const XmlAttribute* xyz = o.attribute("xyz");
  ASSERT_NE(xyz, nullptr);
  EXPECT_EQ(text.substr(xyz->value_begin, xyz->value_end - xyz->value_begin), "1 2 3");
  EXPECT_EQ(xyz->quote, '\'');
  EXPECT_EQ(o.attribute("rpy")->quote, 0);
  const int j2 = xml.child(xml.root, "joint", "name", "j2");
  ASSERT_GE(j2, 0);
  EXPECT_TRUE(xml.elements[static_cast<std::size_t>(j2)].empty);
  EXPECT_EQ(xml.child(j2, "origin"), -1);
  // Without a declaration a comment goes after the byte order mark, or first.
  EXPECT_EQ(scan_urdf_xml("\xEF\xBB\xBF<robot/>").prolog_end, 3u);
  EXPECT_EQ(scan_urdf_xml("<?xml-stylesheet href=\"a\"?><robot/>").prolog_end, 0u);
}

TEST(UrdfXml, EscapesWhatKincalWritesForItsPlace) {
  EXPECT_EQ(xml_comment_text("t--><evil/><!--x"), "t- -><evil/><!- -x");
  EXPECT_EQ(xml_comment_text("a---"), "a- - - ");
  EXPECT_EQ(xml_comment_text("m\x1B[31m\xFF.json"), "m\\x1B[31m\\xFF.json");
  EXPECT_EQ(xml_attribute_text("b\"<x>'&\t\n"), "b&quot;&lt;x&gt;&apos;&amp;&#9;&#10;");
}

}  // namespace
}  // namespace kincal::cli
