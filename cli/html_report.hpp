#pragma once
// Reports for people: one self-contained HTML file (no network, no script) with the plots as
// inline SVG (cli/svg_plot), rendered from a command's JSON report so that every command
// that writes JSON can have a page. The calibration report's page holds: verdicts in plain
// language and what to do next, residuals per configuration and their histogram against the
// noise, parameter corrections with error bars, the correlation heat map, the singular-value
// spectrum with identifiability in words, flagged outliers and warnings. Optional sections
// render when their fields exist (see render_calibration_html). Every string from the report
// (file names, parameter and reading names, messages) is escaped. The page and its building
// blocks are here (html_report.cpp); the calibration report's verdicts are in
// calibration_verdicts.cpp, its sections in calibration_report_sections.{hpp,cpp}, the
// pose-accuracy and sensitivity sections (shared with other pages) in html_pose_accuracy and
// html_sensitivity, the other commands' pages in html_pages.hpp.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace kincal::cli {

/// A plain-language finding and what to do about it.
struct Verdict {
  enum class Level { kGood, kNote, kWarning, kProblem };
  Level level = Level::kNote;
  std::string finding;  ///< what the numbers say
  std::string action;   ///< what to do next; empty when nothing
};

/// The verdicts on a calibration report (the JSON of to_json(CalibrationReport)): the
/// solver's outcome, the noise against the stated reading_std, conditioning and weakly
/// determined directions, the least determined parameters, correlations of +-1, outliers,
/// skipped rows and the report's warnings.
std::vector<Verdict> calibration_verdicts(const nlohmann::ordered_json& report);

/// A page: a head with the styles, sections appended in order.
class HtmlPage {
 public:
  explicit HtmlPage(std::string title);
  /// A section with an anchor id, a heading and HTML content (already escaped).
  void add_section(const std::string& id, const std::string& heading, const std::string& html);
  std::string str() const;

 private:
  std::string title_;
  std::vector<std::string> sections_, toc_;
};

/// The verdicts as an HTML list.
std::string verdicts_html(const std::vector<Verdict>& verdicts);

/// The calibration report's page. Besides the fields calibrate always writes it renders,
/// when present: "predicted_pose_error" (a table, a plot over the workspace, and a verdict when
/// calibration is not expected to beat the nominal model), "target" (calibrate --target: a
/// verdict), "pose_accuracy_shown" false (a note on what the readings cannot show),
/// per-parameter "prior_std" and "data_share" (columns of the parameter table), "sensitivity"
/// (calibrate --sensitivity: a chart and a table) and "warnings".
std::string render_calibration_html(const nlohmann::ordered_json& report);

/// An object or an array of flat objects as an HTML table (keys as headers); nested values
/// are shown as plain text ("key value; key value", lists comma-separated), never as JSON.
std::string json_table_html(const nlohmann::ordered_json& value);

/// A JSON value as plain text for a person: strings as they are, numbers with 5 digits,
/// yes/no, a dash for null, arrays comma-separated, objects as "key value; key value".
std::string plain_text(const nlohmann::ordered_json& value);

/// The identifiability section (singular-value chart, rank and conditioning in words, the
/// weakest combinations) from r["identifiability"] (the JSON of to_json(Identifiability)).
std::string identifiability_html(const nlohmann::ordered_json& r);

}  // namespace kincal::cli
