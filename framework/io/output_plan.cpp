#include "kincal/framework/io/output_plan.hpp"

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal {

namespace {

namespace fs = std::filesystem;

bool g_stop_after_option_checks = false;

// What a path is, for telling whether two paths are the same file.
struct Identity {
  enum class Kind {
    kNone,     // nothing there (an input that does not exist): collides with nothing
    kNode,     // an existing file, device or pipe: device + inode
    kNewName,  // a file to be created: its directory's device + inode, and its name
    kNull,     // the null device: writing it twice or reading it loses nothing
    kStdout,   // standard output when it is no file to compare: closed, or a stream of the
               // caller's (StandardOutput), which no file named by the caller can be
  };
  Kind kind = Kind::kNone;
  dev_t dev = 0;
  ino_t ino = 0;
  std::string name;

  bool collides_with(const Identity& other) const {
    if (kind == Kind::kNone || kind == Kind::kNull || kind != other.kind) return false;
    return kind == Kind::kStdout || (dev == other.dev && ino == other.ino && name == other.name);
  }
};

Identity identity_of(const struct stat& st) {
  Identity id;
  if (S_ISCHR(st.st_mode) && major(st.st_rdev) == 1 && minor(st.st_rdev) == 3) {
    id.kind = Identity::Kind::kNull;
    return id;
  }
  id.kind = Identity::Kind::kNode;
  id.dev = st.st_dev;
  id.ino = st.st_ino;
  return id;
}

Identity stdout_identity(const StandardOutput& standard_output) {
  if (!standard_output.is_process_stdout()) return {Identity::Kind::kStdout, 0, 0, {}};
  struct stat st {};
  if (::fstat(STDOUT_FILENO, &st) != 0) return {Identity::Kind::kStdout, 0, 0, {}};
  return identity_of(st);
}

// An existing path (symbolic links followed), or kNone.
Identity existing_identity(const std::string& path) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0) return {};
  return identity_of(st);
}

Identity output_identity(const OutputTarget& t, const StandardOutput& standard_output) {
  if (t.kind == OutputTarget::Kind::kStdout) return stdout_identity(standard_output);
  if (t.kind == OutputTarget::Kind::kStream || t.exists) return existing_identity(t.real);
  // A new file, maybe in directories still to be created: the nearest existing directory
  // and the path below it.
  const auto [existing, rest] = split_at_existing_directory(t.real);
  Identity id = existing_identity(existing);
  id.kind = Identity::Kind::kNewName;
  id.name = rest;
  return id;
}

std::string quoted(const std::string& label, const std::string& path) {
  return label + " '" + path + "'" + (path == "-" ? " (standard output)" : "");
}

// True when `inner` is `dir` or lies inside it (both absolute, symbolic links resolved).
bool is_inside(const fs::path& inner, const fs::path& dir) {
  const auto [mismatch, unused] = std::mismatch(dir.begin(), dir.end(), inner.begin(), inner.end());
  return mismatch == dir.end();
}

}  // namespace

void stop_after_option_checks(bool stop) { g_stop_after_option_checks = stop; }

void OutputPlan::input(const std::string& label, const std::string& path) {
  entries_.push_back({label, path, false, false, {}});
}

void OutputPlan::output(const std::string& label, const std::string& path) {
  entries_.push_back({label, path, true, false, {}});
}

void OutputPlan::output_directory(const std::string& label, const std::string& path,
                                  const std::vector<std::string>& files) {
  entries_.push_back({label, path, true, true, files});
}

void OutputPlan::check() {
  // Reports and pages (--json, --report, --html) name the files of the run: a name they
  // cannot hold is refused here, before any work, not after it (docs/reliability.md).
  bool names_files = false;
  for (const Entry& e : entries_)
    names_files =
        names_files ||
        (e.is_output && (e.label == "--json" || e.label == "--report" || e.label == "--html"));
  for (const Entry& e : entries_)
    if (names_files && !is_valid_utf8(e.path))
      throw OutputError(e.label + ": the file name is not valid UTF-8 ('" +
                        message_excerpt(e.path) +
                        "'); kincal's reports name their files in JSON, so expected a UTF-8 name "
                        "(rename the file)");
  // Every output must be writable where it is.
  std::vector<Identity> ids(entries_.size());
  std::vector<std::string> reals(entries_.size());  // absolute, links resolved; "" if none
  std::vector<OutputTarget> targets(entries_.size());
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    const std::string what = e.label + " '" + e.path + "'";
    if (e.is_directory) {
      const DirectoryTarget t = resolve_output_directory(e.path, what, e.files);
      reals[i] = t.real;
      if (t.exists) {
        ids[i] = existing_identity(t.real);
      } else {
        const auto [existing, rest] = split_at_existing_directory(t.real);
        ids[i] = existing_identity(existing);
        ids[i].kind = Identity::Kind::kNewName;
        ids[i].name = rest;
      }
    } else if (e.is_output) {
      const OutputTarget t = resolve_output(e.path, what);
      check_can_create_beside(t, what);
      targets[i] = t;
      ids[i] = output_identity(t, *standard_output_);
      if (t.kind == OutputTarget::Kind::kFile) reals[i] = t.real;
    } else {
      ids[i] = existing_identity(e.path);
      std::error_code ec;
      if (ids[i].kind != Identity::Kind::kNone) reals[i] = fs::canonical(e.path, ec).string();
    }
  }
  // Then no output may be an input or another output.
  const Identity out = stdout_identity(*standard_output_);
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry& a = entries_[i];
    if (!a.is_output && ids[i].collides_with(out))
      throw OutputError("standard output goes to " + quoted(a.label, a.path) +
                        ", an input; kincal prints there, expected standard output elsewhere");
    for (std::size_t j = 0; j < i; ++j) {
      const Entry& b = entries_[j];
      if (!a.is_output && !b.is_output) continue;
      const Entry& output = a.is_output ? a : b;
      const Entry& other = a.is_output ? b : a;
      const bool same = ids[i].collides_with(ids[j]);
      const std::size_t dir = a.is_directory ? i : j, inner = a.is_directory ? j : i;
      const bool inside = (a.is_directory || b.is_directory) && !reals[inner].empty() &&
                          is_inside(reals[inner], reals[dir]);
      if (!same && !inside) continue;
      if (other.is_output)
        throw OutputError(quoted(b.label, b.path) + " and " + quoted(a.label, a.path) +
                          (same ? " are the same file" : " lie one inside the other") +
                          "; expected two different files");
      throw OutputError(quoted(output.label, output.path) +
                        (same ? " is the same file as " : " contains ") +
                        quoted(other.label, other.path) +
                        ", an input; expected an output that is not an input (writing it would "
                        "destroy the input)");
    }
  }
  // Last, so that a collision is named as such: an existing output kincal does not replace.
  for (std::size_t i = 0; i < entries_.size(); ++i)
    if (entries_[i].is_output && !entries_[i].is_directory)
      check_replaceable(targets[i], entries_[i].label + " '" + entries_[i].path + "'");
  checked_ = true;
  if (g_stop_after_option_checks) throw OptionsChecked{};
}

bool OutputPlan::to_stdout(const std::string& label) const {
  const Entry& e = find(label, false);
  if (e.path == "-") return true;
  const OutputTarget t = resolve_output(e.path, e.label + " '" + e.path + "'");
  if (t.kind != OutputTarget::Kind::kStream) return false;
  const Identity id = existing_identity(t.real), out = stdout_identity(*standard_output_);
  return id.kind == out.kind && id.dev == out.dev && id.ino == out.ino;
}

const OutputPlan::Entry& OutputPlan::find(const std::string& label, bool directory) const {
  for (const auto& e : entries_)
    if (e.is_output && e.label == label && e.is_directory == directory) return e;
  throw std::logic_error("OutputPlan: no output '" + label + "' was declared");
}

void OutputPlan::write(const std::vector<std::pair<std::string, std::string>>& contents) const {
  if (!checked_) throw std::logic_error("OutputPlan::write before check()");
  std::vector<OutputFile> files;
  for (const auto& [label, content] : contents) files.push_back({find(label, false).path, content});
  write_files_atomically(files, *standard_output_);
}

void OutputPlan::write_directory(
    const std::string& label, const std::vector<std::pair<std::string, std::string>>& files) const {
  if (!checked_) throw std::logic_error("OutputPlan::write_directory before check()");
  const Entry& e = find(label, true);
  // Again now: the directory may have changed during the work, and is replaced whole.
  const DirectoryTarget target =
      resolve_output_directory(e.path, "cannot write " + e.label + " '" + e.path + "'", e.files);
  std::vector<OutputFile> out;
  for (const auto& [name, content] : files) out.push_back({name, content});
  check_standard_output(*standard_output_);  // what was printed comes first, as for files
  write_directory_atomically(target, out);
}

}  // namespace kincal
