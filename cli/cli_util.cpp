#include "kincal/cli/cli_util.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <random>

#include "kincal/framework/solver_registry.hpp"

namespace kincal::cli {

bool parse_command_line(const std::string& command, const Args& args,
                        po::options_description& options, po::variables_map& vm) {
  options.add_options()("help,h", "show this help");
  try {
    // An empty positional description makes boost reject stray words ("too many
    // positional options") instead of ignoring them.
    const po::positional_options_description no_positional;
    po::store(po::command_line_parser(args).options(options).positional(no_positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw CliError(e.what());
  }
  if (vm.count("help")) {
    std::cout << "usage: kincal " << command << " [options]\n" << options << "\n";
    return false;
  }
  return true;
}

void validate(boost::any& out, const std::vector<std::string>& values, Seed*, int) {
  po::validators::check_first_occurrence(out);
  const std::string& text = po::validators::get_single_string(values);
  const bool digits_only =
      !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  try {
    if (!digits_only) throw std::invalid_argument(text);
    out = Seed{std::stoull(text)};
  } catch (const std::exception&) {
    throw po::error("--seed '" + text + "': expected a whole number from 0 to 2^64 - 1");
  }
}

std::map<std::string, std::string> parse_key_values(const std::vector<std::string>& entries,
                                                    const std::string& option_name) {
  std::map<std::string, std::string> out;
  for (const auto& entry : entries) {
    const auto eq = entry.find('=');
    if (eq == std::string::npos || eq == 0)
      throw CliError("--" + option_name + " '" + entry + "': expected key=value");
    const std::string key = entry.substr(0, eq);
    if (out.count(key))
      throw CliError("--" + option_name + " '" + key + "' is given twice ('" + out[key] +
                     "' and '" + entry.substr(eq + 1) + "')");
    out[key] = entry.substr(eq + 1);
  }
  return out;
}

namespace {

namespace fs = std::filesystem;

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

// /proc/self/fd/N and the like (reached from /dev/stdout, /dev/fd/N) are handles to open
// files, not names: their link targets ("pipe:[123]") cannot be written beside.
bool under_proc(const fs::path& p) {
  if (!p.is_absolute()) return false;
  const auto first = ++p.begin();  // after the root "/"
  return first != p.end() && *first == "proc";
}

// The directory of `p`, absolute with every symlink resolved; throws when it is missing.
fs::path real_directory(const fs::path& p, const std::string& what) {
  const fs::path given = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  const fs::path dir = fs::canonical(given, ec);
  if (ec || !fs::is_directory(dir))
    throw CliError(what + ": directory '" + given.string() + "' does not exist");
  return dir;
}

OutputTarget stream_target(OutputTarget t, const fs::path& p, const std::string& what) {
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    throw CliError(what + ": is a directory, expected a file path");
  t.kind = OutputTarget::Kind::kStream;
  t.real = p.string();
  return t;
}

void write_all(int fd, const std::string& content, const std::string& path) {
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw CliError("cannot write '" + path + "': " + errno_text(errno));
    data += n;
    left -= static_cast<std::size_t>(n);
  }
}

// A character device or FIFO: no temporary file, no rename. O_APPEND so that a /dev/stdout
// redirected to a file continues after what was printed before instead of overwriting it.
void write_stream(const OutputTarget& t, const std::string& content) {
  std::cout.flush();
  const int fd = ::open(t.real.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) throw CliError("cannot write '" + t.path + "': " + errno_text(errno));
  try {
    write_all(fd, content, t.path);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw CliError("cannot write '" + t.path + "': " + errno_text(errno));
}

// A new file beside `t.real` with the target's permission bits, holding `content`, flushed
// to disk. Returns its path; removes it and throws on any failure.
std::string write_temporary(const OutputTarget& t, const std::string& content) {
  const fs::path real(t.real);
  std::random_device rd;
  std::string temp;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
    temp = (real.parent_path() /
            ("." + real.filename().string() + ".tmp" + std::to_string(rd() % 1000000)))
               .string();
    // 0666 minus the umask, as for any new file; an existing file's bits are copied below.
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0)
    throw CliError("cannot write '" + t.path + "': cannot create a file in its directory (" +
                   errno_text(errno) + ")");
  try {
    if (t.exists && ::fchmod(fd, static_cast<mode_t>(t.permissions)) != 0)
      throw CliError("cannot write '" + t.path + "': " + errno_text(errno));
    write_all(fd, content, t.path);
    // On disk before the rename, so a crash leaves the old file or the new one, whole.
    if (::fsync(fd) != 0) throw CliError("cannot write '" + t.path + "': " + errno_text(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(temp.c_str());
    throw;
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    throw CliError("cannot write '" + t.path + "': " + errno_text(error));
  }
  return temp;
}

// Best effort: makes the renames themselves durable; their success does not depend on it.
void sync_directory(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

OutputTarget resolve_output(const std::string& path, const std::string& what) {
  OutputTarget t;
  t.path = path;
  if (path == "-") {
    t.kind = OutputTarget::Kind::kStdout;
    return t;
  }
  fs::path p(path);
  if (path.empty()) throw CliError(what + ": empty path, expected a file path");
  for (int links = 0; links <= 40; ++links) {
    const fs::path name = p.filename();
    if (name.empty() || name == "." || name == "..")
      throw CliError(what + ": names a directory, expected a file path");
    p = real_directory(p, what) / name;
    if (under_proc(p)) return stream_target(t, p, what);
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0) {
      if (errno != ENOENT) throw CliError(what + ": " + errno_text(errno));
      t.real = p.string();  // a new file
      return t;
    }
    if (S_ISLNK(st.st_mode)) {
      std::error_code ec;
      const fs::path link = fs::read_symlink(p, ec);
      if (ec) throw CliError(what + ": " + ec.message());
      p = link.is_absolute() ? link : p.parent_path() / link;
      continue;
    }
    if (S_ISDIR(st.st_mode)) throw CliError(what + ": is a directory, expected a file path");
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return stream_target(t, p, what);
    if (!S_ISREG(st.st_mode))
      throw CliError(what + ": is a special file (" +
                     (S_ISBLK(st.st_mode) ? "block device" : "socket") +
                     "), expected a regular file path");
    t.real = p.string();
    t.exists = true;
    t.permissions = st.st_mode & 07777;
    return t;
  }
  throw CliError(what + ": too many levels of symbolic links");
}

void write_files_atomically(const std::vector<OutputFile>& files) {
  std::vector<OutputTarget> targets;
  for (const auto& f : files)
    targets.push_back(resolve_output(f.path, "cannot write '" + f.path + "'"));
  // Phase 1: every regular file into its temporary file. Any failure undoes them all.
  std::vector<std::string> temps(files.size());
  const auto remove_temps = [&temps] {
    for (auto& temp : temps)
      if (!temp.empty()) ::unlink(temp.c_str());
  };
  try {
    for (std::size_t i = 0; i < files.size(); ++i)
      if (targets[i].kind == OutputTarget::Kind::kFile)
        temps[i] = write_temporary(targets[i], files[i].content);
  } catch (...) {
    remove_temps();
    throw;
  }
  // Phase 2: the renames, which cannot run out of space.
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (temps[i].empty()) continue;
    if (::rename(temps[i].c_str(), targets[i].real.c_str()) != 0) {
      const int error = errno;
      remove_temps();
      throw CliError("cannot write '" + files[i].path + "': " + errno_text(error));
    }
    temps[i].clear();
    sync_directory(fs::path(targets[i].real).parent_path().string());
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (targets[i].kind == OutputTarget::Kind::kStdout) {
      std::cout << files[i].content;
      std::cout.flush();
    } else if (targets[i].kind == OutputTarget::Kind::kStream) {
      write_stream(targets[i], files[i].content);
    }
  }
}

void write_file_atomically(const std::string& path, const std::string& content) {
  write_files_atomically({{path, content}});
}

std::string default_solver_name() { return SolverRegistry::global().contains("lm") ? "lm" : "gn"; }

void add_solver_options(po::options_description& options) {
  options.add_options()("solver", po::value<std::string>()->default_value(default_solver_name()),
                        "solver backend (kincal list solvers)")(
      "solver-option", po::value<std::vector<std::string>>()->composing(),
      "backend-specific setting key=value (repeatable; see docs/solvers.md)")(
      "max-iterations", po::value<int>()->default_value(200), "iteration limit of the solver")(
      "verbose,v", po::value<int>()->default_value(0)->implicit_value(1),
      "print one line per solver iteration on stderr; --verbose=2 adds lm's trial steps, "
      "Ceres' log and Ipopt's own output");
}

SolverChoice make_solver_choice(const po::variables_map& vm) {
  SolverChoice choice;
  choice.name = vm["solver"].as<std::string>();
  try {
    choice.solver = SolverRegistry::global().create(choice.name);
    if (vm.count("solver-option"))
      choice.options.backend_options =
          parse_key_values(vm["solver-option"].as<std::vector<std::string>>(), "solver-option");
    choice.options.max_iterations = vm["max-iterations"].as<int>();
    if (choice.options.max_iterations < 0) throw CliError("--max-iterations must be >= 0");
    choice.options.verbosity = vm["verbose"].as<int>();
    if (choice.options.verbosity < 0 || choice.options.verbosity > 2)
      throw CliError("--verbose must be 0, 1 or 2");
    choice.solver->check_options(choice.options);
  } catch (const InvalidSolverOptions& e) {
    throw CliError(e.what());
  }
  return choice;
}

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw CliError("cannot create directory '" + dir + "'" +
                   (ec ? ": " + ec.message() : std::string()));
}

}  // namespace kincal::cli
