#pragma once
// What `kincal run PROJECT.yaml` (cli/command_run.cpp) tells the commands it runs: the
// project step that a JSON report records (framework/io/project_file.hpp: project_record),
// and whether only the options are to be checked (every step's, before the first runs).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace kincal::cli {

/// The record of the step being run; nullopt outside `kincal run`.
void set_active_project_record(std::optional<nlohmann::ordered_json> record);
const std::optional<nlohmann::ordered_json>& active_project_record();

/// `report` as a JSON report's text (2-space indent, final newline), with the key "project"
/// (the active record) when the command runs as a project's step.
std::string json_report_text(nlohmann::ordered_json report);

/// When set, parse_command_line throws OptionsChecked once the options are parsed: a
/// project's steps are checked for unknown or malformed options before any of them runs.
void set_parse_only(bool parse_only);
bool parse_only();

}  // namespace kincal::cli
