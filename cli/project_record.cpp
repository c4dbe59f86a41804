#include "kincal/cli/project_record.hpp"

namespace kincal::cli {

namespace {
std::optional<nlohmann::ordered_json>& record_storage() {
  static std::optional<nlohmann::ordered_json> record;
  return record;
}
bool g_parse_only = false;
}  // namespace

void set_active_project_record(std::optional<nlohmann::ordered_json> record) {
  record_storage() = std::move(record);
}

const std::optional<nlohmann::ordered_json>& active_project_record() { return record_storage(); }

std::string json_report_text(nlohmann::ordered_json report) {
  if (record_storage() && report.is_object()) report["project"] = *record_storage();
  return report.dump(2) + "\n";
}

void set_parse_only(bool parse_only) { g_parse_only = parse_only; }
bool parse_only() { return g_parse_only; }

}  // namespace kincal::cli
