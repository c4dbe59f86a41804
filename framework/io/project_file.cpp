#include "kincal/framework/io/project_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/base/nearest_name.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal {

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxProjectBytes = std::size_t{1} << 20;
// Steps nest two levels (steps -> command -> option); a value nests at most one more (a list
// or a map). Anything deeper is a mistake, refused before recursion could cost the stack.
constexpr int kMaxDepth = 8;
// Aliases (*name) share nodes, so a small text can stand for a tree of 1000^8 values: the walk
// counts the values it visits and stops at this many (a real project has a few hundred).
constexpr long kMaxValues = 100000;

const std::vector<std::string> kTopLevelKeys = {"name", "variables", "steps"};

// The options that name a file or folder, for every command that has them.
const std::set<std::string> kPathOptions = {
    "model",       "data",    "out",     "json",     "html",   "report",
    "before",      "images",  "urdf",    "configs",  "truth",  "write-data",
    "trace",       "targets", "nominal", "existing", "within", "candidates-file",
    "start-model", "plugin"};

class Reader {
 public:
  Reader(std::string file, const std::vector<std::pair<std::string, std::string>>& overrides)
      : file_(std::move(file)), overrides_(overrides) {}

  // `where` and `what` quote the file's keys and values, which may hold line breaks (a quoted
  // or block-scalar key) or run long: each is cut and escaped so the message stays one line.
  [[noreturn]] void fail(int line, const std::string& where, const std::string& what) const {
    throw ProjectError(file_ + ":" + std::to_string(line) + ": " +
                       (where.empty() ? "" : message_excerpt(where, 120) + ": ") +
                       message_excerpt(what, 400));
  }

  static int line_of(const YAML::Node& node) { return node.Mark().line + 1; }

  void check_depth(const YAML::Node& node, int depth) {
    if (depth > kMaxDepth)
      fail(line_of(node), "", "nesting deeper than " + std::to_string(kMaxDepth) + " levels");
    if (++values_seen_ > kMaxValues)
      fail(line_of(node), "",
           "more than " + std::to_string(kMaxValues) + " values (aliases expanded)");
    if (node.IsMap())
      for (const auto& pair : node) check_depth(pair.second, depth + 1);
    else if (node.IsSequence())
      for (const auto& item : node) check_depth(item, depth + 1);
  }

  std::string scalar(const YAML::Node& node, const std::string& where) const {
    if (!node.IsScalar())
      fail(line_of(node), where,
           std::string("expected a value (text or number), got ") + (node.IsMap() ? "a map"
                                                                     : node.IsSequence()
                                                                         ? "a list"
                                                                         : "nothing"));
    return node.Scalar();
  }

  // ${name} replaced by the variable's value; "$" elsewhere is itself.
  std::string substitute(const std::string& text, int line, const std::string& where) const {
    std::string result;
    for (std::size_t i = 0; i < text.size();) {
      if (text.compare(i, 2, "${") != 0) {
        result += text[i++];
        continue;
      }
      const std::size_t close = text.find('}', i + 2);
      if (close == std::string::npos) fail(line, where, "'${' without its '}' in '" + text + "'");
      const std::string name = text.substr(i + 2, close - i - 2);
      const auto found = variables_.find(name);
      if (found == variables_.end()) {
        std::vector<std::string> known;
        for (const auto& [key, value] : variables_) known.push_back(key);
        const std::string near = nearest_name(name, known);
        fail(line, where,
             "${" + name + "} is not a variable of this project" +
                 (near.empty() ? "" : " (did you mean ${" + near + "}?)") +
                 (known.empty() ? "; it declares none (variables: {NAME: VALUE})"
                                : "; it declares " + join(known)));
      }
      result += found->second;
      i = close + 1;
    }
    return result;
  }

  static std::string join(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
  }

  void read_variables(const YAML::Node& node) {
    if (node && !node.IsNull()) {
      if (!node.IsMap()) fail(line_of(node), "variables", "expected a map of NAME: VALUE");
      for (const auto& pair : node) {
        const std::string name = scalar(pair.first, "variables");
        if (name.empty() || name.find_first_of("${} ") != std::string::npos)
          fail(line_of(pair.first), "variables", "'" + name + "' is not a variable name");
        if (variables_.count(name))
          fail(line_of(pair.first), "variables", "'" + name + "' appears twice");
        variables_[name] = scalar(pair.second, "variables." + name);
      }
    }
    for (const auto& [name, value] : overrides_) {
      if (!variables_.count(name)) {
        std::vector<std::string> known;
        for (const auto& [key, unused] : variables_) known.push_back(key);
        const std::string near = nearest_name(name, known);
        const std::string shown = message_excerpt(name, 60);
        throw ProjectError("--set " + shown + ": " + file_ + " declares no variable '" + shown +
                           "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                           (known.empty() ? "" : "; it declares " + join(known)));
      }
      if (!is_valid_utf8(value))
        throw ProjectError("--set " + message_excerpt(name, 60) + ": the value is not UTF-8 text");
      variables_[name] = value;
    }
  }

  std::string resolve(const std::string& command, const std::string& key,
                      const std::string& value) const {
    if (!project_path_option(command, key) || value.empty() || value == "-") return value;
    const fs::path path(value);
    if (path.is_absolute()) return value;
    return (fs::path(folder_) / path).lexically_normal().string();
  }

  ProjectOption read_option(const std::string& command, const YAML::Node& key_node,
                            const YAML::Node& value, const std::string& where) const {
    ProjectOption option;
    option.line = line_of(key_node);
    option.key = scalar(key_node, where);
    std::replace(option.key.begin(), option.key.end(), '_', '-');
    if (option.key.empty() || option.key[0] == '-')
      fail(option.line, where,
           "'" + option.key + "' is not an option name (write it without the dashes)");
    const std::string at = where + "." + option.key;
    auto text = [&](const YAML::Node& node) {
      return resolve(command, option.key, substitute(scalar(node, at), line_of(node), at));
    };
    if (value.IsScalar() && value.Tag() != "!" &&
        (value.Scalar() == "true" || value.Scalar() == "True" || value.Scalar() == "TRUE")) {
      option.is_switch = true;
    } else if (value.IsScalar() && value.Tag() != "!" &&
               (value.Scalar() == "false" || value.Scalar() == "False" ||
                value.Scalar() == "FALSE")) {
      option.is_switch = true;
      option.values = {"false"};  // left out by project_step_arguments
    } else if (value.IsScalar()) {
      option.values.push_back(text(value));
    } else if (value.IsSequence()) {
      if (value.size() == 0) fail(option.line, at, "an empty list: leave the key out instead");
      for (const YAML::Node& item : value) option.values.push_back(text(item));
    } else if (value.IsMap()) {
      for (const auto& pair : value) {
        const std::string name = scalar(pair.first, at);
        option.values.push_back(name + "=" + text(pair.second));
      }
    } else {
      fail(option.line, at, "no value: give one, or leave the key out");
    }
    return option;
  }

  ProjectStep read_step(const YAML::Node& node, std::size_t index) const {
    const std::string where = "steps[" + std::to_string(index + 1) + "]";
    if (!node.IsMap() || node.size() != 1)
      fail(line_of(node), where,
           "expected one command with its options, e.g. '- calibrate: {model: M.json, data: "
           "D.csv}'");
    const auto& pair = *node.begin();
    ProjectStep step;
    step.command = scalar(pair.first, where);
    step.line = line_of(pair.first);
    const std::string at = where + "." + step.command;
    const YAML::Node& options = pair.second;
    if (options.IsNull()) return step;  // a command without options
    if (!options.IsMap())
      fail(line_of(options), at, "expected the command's options as a map of key: value");
    std::set<std::string> seen;
    for (const auto& option : options) {
      ProjectOption read = read_option(step.command, option.first, option.second, at);
      if (!seen.insert(read.key).second)
        fail(read.line, at,
             "option '" + read.key + "' appears twice (give several values as a list)");
      step.options.push_back(std::move(read));
    }
    return step;
  }

  Project read(const std::string& text) {
    Project project;
    project.file = file_;
    project.folder = fs::absolute(fs::path(file_)).parent_path().lexically_normal().string();
    folder_ = project.folder;
    project.content = text;
    project.sha256 = sha256_hex(text);
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      // Inside a flow map ({...}) the braces of ${NAME} end the map: say so.
      const bool flow_hint =
          text.find("${") != std::string::npos && e.msg.find("flow") != std::string::npos;
      fail(e.mark.line + 1, "",
           "malformed YAML: " + e.msg +
               (flow_hint ? " (a value with ${NAME} inside {...} must be quoted: '${NAME}/file')"
                          : ""));
    }
    if (!root.IsMap())
      fail(root ? line_of(root) : 1, "",
           "expected a project: a map with 'steps' (and optionally 'name', 'variables')");
    check_depth(root, 0);
    std::set<std::string> seen;
    for (const auto& pair : root) {
      const std::string key = scalar(pair.first, "");
      if (!seen.insert(key).second) fail(line_of(pair.first), key, "appears twice");
      if (std::find(kTopLevelKeys.begin(), kTopLevelKeys.end(), key) == kTopLevelKeys.end()) {
        const std::string near = nearest_name(key, kTopLevelKeys);
        fail(line_of(pair.first), key,
             "not a key of a project" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                 "; expected name, variables, steps");
      }
    }
    if (root["name"]) project.name = scalar(root["name"], "name");
    read_variables(root["variables"]);
    project.variables = variables_;
    const YAML::Node steps = root["steps"];
    if (!steps || !steps.IsSequence() || steps.size() == 0)
      fail(steps ? line_of(steps) : 1, "steps",
           "expected a non-empty list of steps, e.g. '- calibrate: {model: M.json, data: D.csv}'");
    for (std::size_t i = 0; i < steps.size(); ++i) project.steps.push_back(read_step(steps[i], i));
    return project;
  }

 private:
  std::string file_;
  std::string folder_;
  const std::vector<std::pair<std::string, std::string>>& overrides_;
  std::map<std::string, std::string> variables_;
  long values_seen_ = 0;
};

}  // namespace

Project parse_project(const std::string& text, const std::string& path,
                      const std::vector<std::pair<std::string, std::string>>& overrides) {
  if (text.size() > kMaxProjectBytes)
    throw ProjectError(path + ":1: larger than the limit of 1 MiB for a project file");
  if (text.find('\0') != std::string::npos)
    throw ProjectError(path + ":1: holds a NUL byte; expected a project file (YAML or JSON text)");
  // Reports record the content as JSON text, which is UTF-8: refuse other bytes here, at the
  // line of the first line that is not UTF-8.
  if (!is_valid_utf8(text)) {
    int line = 1;
    for (std::size_t start = 0; start < text.size(); ++line) {
      const std::size_t end = std::min(text.find('\n', start), text.size());
      if (!is_valid_utf8(text.substr(start, end - start))) break;
      start = end + 1;
    }
    throw ProjectError(path + ":" + std::to_string(line) +
                       ": not UTF-8 text; expected a project file in UTF-8 (save it as UTF-8)");
  }
  return Reader(path, overrides).read(text);
}

Project read_project(const std::string& path,
                     const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::string text;
  try {
    text = read_file_text(path, "project file (YAML)", kMaxProjectBytes);
  } catch (const std::invalid_argument& e) {
    throw ProjectError(e.what());
  }
  return parse_project(text, path, overrides);
}

bool project_path_option(const std::string& command, const std::string& key) {
  if (key == "poses") return command == "detect" || command == "ik";
  if (key == "mechanism") return command == "detect";
  return kPathOptions.count(key) > 0;
}

std::vector<std::string> project_step_arguments(const ProjectStep& step) {
  std::vector<std::string> args;
  for (const ProjectOption& option : step.options) {
    if (option.is_switch) {
      if (option.values.empty()) args.push_back("--" + option.key);
      continue;
    }
    for (const std::string& value : option.values) {
      args.push_back("--" + option.key);
      args.push_back(value);
    }
  }
  return args;
}

std::string project_step_location(const Project& project, std::size_t index) {
  const ProjectStep& step = project.steps.at(index);
  return project.file + ":" + std::to_string(step.line) + ": steps[" + std::to_string(index + 1) +
         "]." + step.command;
}

int project_key_line(const ProjectStep& step, const std::string& message) {
  for (const ProjectOption& option : step.options) {
    const std::string named = "--" + option.key;
    for (std::size_t at = message.find(named); at != std::string::npos;
         at = message.find(named, at + 1)) {
      const std::size_t end = at + named.size();
      // "--free" must not match "--free-x": the name ends where a name character does not follow.
      if (end == message.size() || !(std::isalnum(static_cast<unsigned char>(message[end])) ||
                                     message[end] == '-' || message[end] == '_'))
        return option.line;
    }
  }
  // A message about a file names the path, not the option: the option holding that value.
  for (const ProjectOption& option : step.options)
    for (const std::string& value : option.values)
      if (value.size() >= 3 && message.find(value) != std::string::npos) return option.line;
  return step.line;
}

nlohmann::ordered_json project_record(const Project& project, std::size_t step_index) {
  nlohmann::ordered_json variables = nlohmann::ordered_json::object();
  for (const auto& [name, value] : project.variables) variables[name] = value;
  return {{"file", fs::absolute(fs::path(project.file)).lexically_normal().string()},
          {"sha256", project.sha256},
          {"step", step_index + 1},
          {"command", project.steps.at(step_index).command},
          {"variables", variables},
          {"content", project.content}};
}

Project project_from_report(const nlohmann::ordered_json& report, const std::string& source,
                            const std::vector<std::pair<std::string, std::string>>& overrides) {
  const auto record = report.is_object() ? report.find("project") : report.end();
  if (!report.is_object() || record == report.end() || !record->is_object())
    throw ProjectError(source +
                       ": records no project (only a report written by a step of `kincal run "
                       "PROJECT` does)");
  auto text = [&](const char* key) {
    const auto found = record->find(key);
    if (found == record->end() || !found->is_string())
      throw ProjectError(source + ": project." + key + ": expected a string");
    return found->get<std::string>();
  };
  const std::string content = text("content"), file = text("file");
  if (sha256_hex(content) != text("sha256"))
    throw ProjectError(source +
                       ": project.content does not match its project.sha256 (the "
                       "report was edited)");
  std::vector<std::pair<std::string, std::string>> variables;
  const auto recorded = record->find("variables");
  if (recorded != record->end() && recorded->is_object())
    for (const auto& [name, value] : recorded->items())
      if (value.is_string()) variables.emplace_back(name, value.get<std::string>());
  for (const auto& item : overrides) variables.push_back(item);
  return parse_project(content, file, variables);
}

}  // namespace kincal
