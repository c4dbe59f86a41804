#include "kincal/framework/report/html_page.hpp"

namespace kincal::report {

namespace {

const char* level_class(Finding::Level level) {
  switch (level) {
    case Finding::Level::kGood:
      return "good";
    case Finding::Level::kNote:
      return "note";
    case Finding::Level::kWarning:
      return "warning";
    case Finding::Level::kDoNotLoad:
      return "problem";
  }
  return "note";
}

const char* level_word(Finding::Level level) {
  switch (level) {
    case Finding::Level::kGood:
      return "OK";
    case Finding::Level::kNote:
      return "Note";
    case Finding::Level::kWarning:
      return "Warning";
    case Finding::Level::kDoNotLoad:
      return "Problem";
  }
  return "";
}

const char* kStyle = R"(
body{font-family:sans-serif;margin:24px auto;padding:0 16px;max-width:1100px;color:#222;line-height:1.4}
h1{font-size:1.5em;margin-bottom:.2em} h2{font-size:1.2em;border-bottom:1px solid #ccc;margin-top:1.6em}
table{border-collapse:collapse;font-size:.9em;margin:.5em 0} td,th{border:1px solid #ddd;padding:2px 8px;text-align:right}
th{background:#f4f4f4} td.name,th.name{text-align:left;font-family:monospace}
nav a{margin-right:1em} .small{font-size:.85em;color:#555}
ul.verdicts{list-style:none;padding-left:0} ul.verdicts li{margin:.4em 0;padding:.4em .6em;border-left:5px solid #999;background:#fafafa}
li.good{border-color:#2e8b57!important} li.note{border-color:#4a78b0!important}
li.warning{border-color:#e0a100!important} li.problem{border-color:#c0392b!important}
.level{font-weight:bold;margin-right:.4em} .action{display:block;color:#333;font-style:italic}
tr.weak td{background:#fff4e0} tr.outlier td{background:#fde8e6}
svg{display:block;margin:.6em 0;background:#fff}
svg .frame{fill:none;stroke:#888} svg .grid{stroke:#eee} svg .tick{font-size:10px;fill:#555}
svg .axis-label{font-size:11px;fill:#333} svg .chart-title{font-size:12px;font-weight:bold;fill:#222}
svg .zero{stroke:#444;stroke-width:1} svg .noise{stroke:#2e8b57;stroke-dasharray:4 3;stroke-width:1.2}
svg .threshold{stroke:#c0392b;stroke-dasharray:6 3;stroke-width:1.2}
svg .bar{fill:#7a9cc6;stroke:#fff} svg .curve{fill:none;stroke:#2e8b57;stroke-width:2}
svg .curve2{fill:none;stroke:#8e44ad;stroke-width:2;stroke-dasharray:5 3}
svg .errbar{stroke:#333;stroke-width:1.3} svg .est{fill:#1f5fa8} svg .est-weak{fill:#e0a100}
svg .sv{fill:#1f5fa8} svg .sv-weak{fill:#e0a100} svg .sv-null{fill:#c0392b}
svg .outlier-ring{fill:none;stroke:#c0392b;stroke-width:1.5} svg .legend{font-size:10px;fill:#333}
svg .s0{fill:#1f5fa8} svg .s1{fill:#2e8b57} svg .s2{fill:#8e44ad} svg .s3{fill:#d35400} svg .s4{fill:#16a085} svg .s5{fill:#7f8c8d}
svg .label{font-size:10px;fill:#222;font-family:monospace}
div.views{display:flex;flex-wrap:wrap;gap:10px} figure.view{margin:0;font-size:.8em;text-align:center}
figure.view svg{margin:0 0 2px 0;border:1px solid #ccc} svg .blank{fill:#f2f2f2}
svg .seen{fill:none;stroke:#1f5fa8} svg .residual{stroke:#d0021b}
)";

}  // namespace

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

void HtmlPage::add_section(const std::string& id, const std::string& heading,
                           const std::string& html) {
  toc_.push_back("<a href=\"#" + esc(id) + "\">" + esc(heading) + "</a>");
  sections_.push_back("<section id=\"" + esc(id) + "\"><h2>" + esc(heading) + "</h2>" + html +
                      "</section>\n");
}

std::string HtmlPage::str() const {
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"/>"
      "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src "
      "'unsafe-inline'; img-src data:\"/>"
      "<title>" +
      esc(title_) + "</title><style>" + kStyle + "</style></head>\n<body><h1>" + esc(title_) +
      "</h1>\n<nav>";
  for (const auto& link : toc_) out += link;
  out += "</nav>\n";
  for (const auto& s : sections_) out += s;
  out +=
      "<p class=\"small\">Written by kincal. This file needs no network and no script.</p>"
      "</body></html>\n";
  return out;
}

std::string findings_html(const std::vector<Finding>& findings) {
  std::string out = "<ul class=\"verdicts\">";
  for (const auto& v : findings) {
    out += "<li class=\"" + std::string(level_class(v.level)) + "\"><span class=\"level\">" +
           level_word(v.level) + "</span>" + esc(v.text);
    if (!v.advice.empty())
      out += "<span class=\"action\">\xE2\x86\x92 " + esc(v.advice) + "</span>";
    out += "</li>";
  }
  return out + "</ul>";
}

std::string summary_row(const std::string& key, const std::string& value) {
  return "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
         "</td></tr>";
}

}  // namespace kincal::report
