#pragma once
// The tests' strict reader of the markup the pages for people are (framework/report/): shared
// by the report layer's tests (tests/framework/report_pages*_test.cpp) and the program's
// (tests/cli/html_report_test.cpp).

#include <algorithm>
#include <regex>
#include <string>
#include <vector>

namespace kincal::testing {

// A strict reader of the markup we write: every element closed in order (or self-closed,
// or a void HTML element), attribute values quoted, '&' only as an entity, no '<' in text.
// Returns "" when well-formed, else what is wrong and where.
inline std::string markup_problem(const std::string& s) {
  static const std::vector<std::string> kVoid = {"meta", "br", "hr", "img", "link", "input"};
  std::vector<std::string> open;
  std::size_t i = 0;
  if (s.rfind("<!DOCTYPE html>", 0) == 0) i = s.find('>') + 1;
  while (i < s.size()) {
    const char c = s[i];
    if (c == '&') {
      static const std::regex entity("^&(amp|lt|gt|quot|#[0-9]+);");
      if (!std::regex_search(s.substr(i, 10), entity)) return "bare & at " + std::to_string(i);
      ++i;
      continue;
    }
    if (c == '>') return "bare > at " + std::to_string(i);
    if (c != '<') {
      ++i;
      continue;
    }
    const std::size_t end = s.find('>', i);
    if (end == std::string::npos) return "unclosed tag at " + std::to_string(i);
    std::string tag = s.substr(i + 1, end - i - 1);
    if (tag.find('<') != std::string::npos) return "< inside a tag at " + std::to_string(i);
    i = end + 1;
    if (tag.rfind("?xml", 0) == 0 || tag.rfind("!--", 0) == 0) continue;
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || open.back() != name)
        return "</" + name + "> closes <" + (open.empty() ? "" : open.back()) + ">";
      open.pop_back();
      continue;
    }
    const bool self_closed = tag.back() == '/';
    if (self_closed) tag.pop_back();
    const std::string name = tag.substr(0, tag.find_first_of(" \n"));
    // Attributes: name="value" with no quote inside the value.
    static const std::regex attrs(R"re(^[a-zA-Z0-9:-]+(\s+[a-zA-Z0-9:-]+="[^"]*")*\s*$)re");
    if (!std::regex_match(tag, attrs)) return "malformed tag <" + tag.substr(0, 80) + ">";
    if (!self_closed && std::find(kVoid.begin(), kVoid.end(), name) == kVoid.end())
      open.push_back(name);
  }
  return open.empty() ? "" : "<" + open.back() + "> never closed";
}

}  // namespace kincal::testing
