#include "kincal/framework/io/output_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>

namespace kincal {

namespace {

namespace fs = std::filesystem;

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

[[noreturn]] void fail_errno(const std::string& path, int error) {
  throw OutputError("cannot write '" + path + "': " + errno_text(error));
}

// Test hook for the crash tests (output_files.hpp): with KINCAL_TEST_KILL_AT_WRITE_STEP=N in
// the environment, the process kills itself at the N-th step of writing files.
void write_step() {
  static const long kill_at = [] {
    const char* text = std::getenv("KINCAL_TEST_KILL_AT_WRITE_STEP");
    return text ? std::atol(text) : 0L;
  }();
  static std::atomic<long> step{0};
  if (kill_at > 0 && ++step == kill_at) std::raise(SIGKILL);
}

// ---- temporary names ---------------------------------------------------------------------

constexpr const char* kTempTag = ".kincal-tmp-";

// ".<name>.kincal-tmp-<pid>-<random hex>". The name is shortened so that the whole stays
// within the 255 bytes a file name may have.
std::string temporary_name(const std::string& target_name) {
  thread_local std::random_device rd;  // the library may write from several threads
  char suffix[40];
  std::snprintf(suffix, sizeof suffix, "%s%ld-%08x", kTempTag, static_cast<long>(::getpid()),
                static_cast<unsigned>(rd()));
  return "." + target_name.substr(0, 200) + suffix;
}

// The writer's process id of a temporary name, or 0 when `name` is not one.
pid_t writer_of(const std::string& name) {
  if (name.empty() || name[0] != '.') return 0;
  const auto tag = name.rfind(kTempTag);
  if (tag == std::string::npos) return 0;
  const std::string rest = name.substr(tag + std::char_traits<char>::length(kTempTag));
  const auto dash = rest.find('-');
  if (dash == 0 || dash == std::string::npos || dash > 9) return 0;
  if (rest.find_first_not_of("0123456789") != dash) return 0;
  if (rest.size() == dash + 1 ||
      rest.find_first_not_of("0123456789abcdef", dash + 1) != std::string::npos)
    return 0;
  return static_cast<pid_t>(std::stol(rest.substr(0, dash)));
}

bool process_is_gone(pid_t pid) {
  return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

// A temporary directory holds only the files a writer put there (or, after a swap, the
// files of the directory it replaced, which held only such files).
void remove_directory_of_files(const fs::path& dir) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_regular_file(ec) && !entry.is_symlink(ec)) ::unlink(entry.path().c_str());
  ::rmdir(dir.c_str());
}

// Best effort: removes the temporary files and directories in `dir` of writers that are
// no longer running.
void remove_stale_temporaries(const fs::path& dir) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const pid_t pid = writer_of(entry.path().filename().string());
    if (pid <= 0 || !process_is_gone(pid)) continue;
    if (entry.is_directory(ec) && !entry.is_symlink(ec))
      remove_directory_of_files(entry.path());
    else
      ::unlink(entry.path().c_str());
  }
}

std::string octal_mode(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

// ---- writing -----------------------------------------------------------------------------

// /proc/self/fd/N and the like (reached from /dev/stdout, /dev/fd/N) are handles to open
// files, not names: their link targets ("pipe:[123]") cannot be written beside.
bool under_proc(const fs::path& p) {
  if (!p.is_absolute()) return false;
  const auto first = ++p.begin();  // after the root "/"
  return first != p.end() && *first == "proc";
}

// The directory of `p`, absolute with every symlink resolved. A directory that does not exist
// yet is its nearest existing ancestor (resolved) with the missing names appended: it is
// created when the file is written (the same rule for every output, docs/reliability.md).
fs::path real_directory(const fs::path& p, const std::string& what) {
  const fs::path given = p.has_parent_path() ? p.parent_path() : fs::path(".");
  fs::path existing = given, missing;
  for (;;) {
    struct stat st {};
    if (::stat(existing.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode))
        throw OutputError(what + ": '" + existing.string() + "' is not a directory");
      break;
    }
    const int error = errno;
    if (error != ENOENT && error != ENOTDIR)
      throw OutputError(what + ": directory '" + given.string() + "': " + errno_text(error));
    if (::lstat(existing.c_str(), &st) == 0)
      throw OutputError(what + ": '" + existing.string() + "' is a broken symbolic link");
    const fs::path name = existing.filename();
    if (name.empty() || name == "." || name == "..")
      throw OutputError(what + ": directory '" + given.string() +
                        "' does not exist (and goes through '" + name.string() +
                        "'); expected a path to an existing or new directory without . or ..");
    missing = missing.empty() ? name : name / missing;
    existing = existing.has_parent_path() ? existing.parent_path() : fs::path(".");
  }
  std::error_code ec;
  const fs::path dir = fs::canonical(existing, ec);
  if (ec) throw OutputError(what + ": directory '" + existing.string() + "': " + ec.message());
  return missing.empty() ? dir : dir / missing;
}

// The nearest existing directory at or above `dir` (absolute).
fs::path nearest_existing_directory(fs::path dir) {
  struct stat st {};
  while (::stat(dir.c_str(), &st) != 0 && dir.has_parent_path() && dir != dir.root_path())
    dir = dir.parent_path();
  return dir;
}

// Creates `dir` and its missing parents; returns the ones created, outermost first.
std::vector<fs::path> create_missing_directories(const fs::path& dir, const std::string& shown) {
  std::vector<fs::path> missing;
  struct stat st {};
  for (fs::path d = dir; ::stat(d.c_str(), &st) != 0 && d.has_parent_path() && d != d.root_path();
       d = d.parent_path())
    missing.insert(missing.begin(), d);
  for (std::size_t i = 0; i < missing.size(); ++i) {
    if (::mkdir(missing[i].c_str(), 0777) != 0 && errno != EEXIST) {
      const int error = errno;
      for (std::size_t k = i; k-- > 0;) ::rmdir(missing[k].c_str());
      throw OutputError("cannot write '" + shown + "': cannot create directory '" +
                        missing[i].string() + "' (" + errno_text(error) + ")");
    }
  }
  return missing;
}

OutputTarget stream_target(OutputTarget t, const fs::path& p, const std::string& what) {
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    throw OutputError(what + ": is a directory, expected a file path");
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
    if (n < 0) fail_errno(path, errno);
    data += n;
    left -= static_cast<std::size_t>(n);
  }
}

// Whatever the caller printed so far, then `content`, on its standard output, checked: a full
// disk, a closed standard output or a broken device is an error, never a silent loss. The
// program's is its out() (cli/console.hpp): std::cout, which a caller of run() may have
// pointed elsewhere (the fuzzers do), or the stream an in-process caller gave the command.
void write_standard_output(const StandardOutput& standard_output, const std::string& content) {
  errno = 0;
  std::ostream& stream = standard_output.stream();
  stream << content;
  stream.flush();
  bool failed = !stream;
  // What anything else in the process wrote on stdio's stdout comes before the files too.
  const bool process = standard_output.is_process_stdout();
  if (process) failed = std::fflush(stdout) != 0 || failed;
  const int error = errno;
  if (failed || (process && std::ferror(stdout))) {
    stream.clear();
    if (process) std::clearerr(stdout);
    throw OutputError("cannot write standard output" +
                      (error != 0 ? ": " + errno_text(error) : std::string()));
  }
}

// A character device or FIFO: no temporary file, no rename. O_APPEND so that a /dev/stdout
// redirected to a file continues after what was printed before instead of overwriting it.
void write_stream(const OutputTarget& t, const std::string& content,
                  const StandardOutput& standard_output) {
  write_standard_output(standard_output, "");  // what was printed before comes first
  const int fd = ::open(t.real.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) fail_errno(t.path, errno);
  try {
    write_all(fd, content, t.path);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) fail_errno(t.path, errno);
}

// A new file `path` holding `content`, flushed to disk, with mode `permissions` when
// `set_permissions`. Removes it and throws on any failure; `shown` names it in messages.
void write_new_file(const std::string& path, const std::string& content, bool set_permissions,
                    unsigned permissions, const std::string& shown) {
  // 0666 minus the umask, as for any new file; an existing file's bits are copied below.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0)
    throw OutputError("cannot write '" + shown + "': cannot create a file in its directory (" +
                      errno_text(errno) + ")");
  write_step();
  try {
    if (set_permissions && ::fchmod(fd, static_cast<mode_t>(permissions)) != 0)
      fail_errno(shown, errno);
    write_all(fd, content, shown);
    write_step();
    // On disk before the rename, so a crash leaves the old file or the new one, whole.
    if (::fsync(fd) != 0) fail_errno(shown, errno);
    write_step();
  } catch (...) {
    ::close(fd);
    ::unlink(path.c_str());
    throw;
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(path.c_str());
    fail_errno(shown, error);
  }
}

// Best effort: makes renames in `dir` durable; their success does not depend on it.
void sync_directory(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// An exclusive flock(2) on each directory the renames of one write go into, held while they
// run: two kincal processes writing the same outputs (two calibrate runs on one
// --out and --json) then rename their sets one after the other, never interleaved, so the
// files left are one run's set (a report and the model it describes). The locks are taken in
// (device, inode) order, so that two writers cannot each hold one the other waits for; they
// are on the directories themselves, so no lock file is left anywhere. Best effort: a
// directory that cannot be opened (no read permission) or a file system without flock goes
// unlocked, as before.
class RenameLocks {
 public:
  explicit RenameLocks(const std::vector<std::string>& directories) {
    struct Opened {
      dev_t device;
      ino_t inode;
      int fd;
    };
    std::vector<Opened> opened;
    for (const std::string& dir : directories) {
      const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd < 0) continue;
      struct stat st {};
      bool seen = ::fstat(fd, &st) != 0;
      for (const Opened& o : opened) seen = seen || (o.device == st.st_dev && o.inode == st.st_ino);
      if (seen) {
        ::close(fd);
        continue;
      }
      opened.push_back({st.st_dev, st.st_ino, fd});
    }
    std::sort(opened.begin(), opened.end(), [](const Opened& a, const Opened& b) {
      return a.device != b.device ? a.device < b.device : a.inode < b.inode;
    });
    for (const Opened& o : opened) {
      while (::flock(o.fd, LOCK_EX) != 0 && errno == EINTR) {
      }
      fds_.push_back(o.fd);  // closing it releases the lock (also if flock failed)
    }
  }
  ~RenameLocks() {
    for (const int fd : fds_) ::close(fd);
  }
  RenameLocks(const RenameLocks&) = delete;
  RenameLocks& operator=(const RenameLocks&) = delete;

 private:
  std::vector<int> fds_;
};

// Test hook: with KINCAL_TEST_PAUSE_BETWEEN_RENAMES_MS=N in the environment, a multi-file
// write sleeps N milliseconds between two renames, so that a test can make another kincal
// process write the same outputs in that window (tests/cli/audit3/plugins.sh). Without it,
// nothing happens.
void pause_between_renames() {
  static const long pause_ms = [] {
    const char* text = std::getenv("KINCAL_TEST_PAUSE_BETWEEN_RENAMES_MS");
    return text ? std::atol(text) : 0L;
  }();
  if (pause_ms > 0) ::usleep(static_cast<useconds_t>(std::min(pause_ms, 10000L)) * 1000);
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
  if (path.empty()) throw OutputError(what + ": empty path, expected a file path");
  for (int links = 0; links <= 40; ++links) {
    const fs::path name = p.filename();
    if (name.empty() || name == "." || name == "..")
      throw OutputError(what + ": names a directory, expected a file path");
    p = real_directory(p, what) / name;
    if (under_proc(p)) return stream_target(t, p, what);
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0) {
      if (errno != ENOENT) throw OutputError(what + ": " + errno_text(errno));
      t.real = p.string();  // a new file
      return t;
    }
    if (S_ISLNK(st.st_mode)) {
      std::error_code ec;
      const fs::path link = fs::read_symlink(p, ec);
      if (ec) throw OutputError(what + ": " + ec.message());
      p = link.is_absolute() ? link : p.parent_path() / link;
      continue;
    }
    if (S_ISDIR(st.st_mode)) throw OutputError(what + ": is a directory, expected a file path");
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return stream_target(t, p, what);
    if (!S_ISREG(st.st_mode))
      throw OutputError(what + ": is a special file (" +
                        (S_ISBLK(st.st_mode) ? "block device" : "socket") +
                        "), expected a regular file path");
    t.real = p.string();
    t.exists = true;
    t.permissions = st.st_mode & 07777;
    t.links = static_cast<unsigned long>(st.st_nlink);
    t.writable = (st.st_mode & 0222) != 0 && (::getuid() == 0 || ::access(p.c_str(), W_OK) == 0);
    return t;
  }
  throw OutputError(what + ": too many levels of symbolic links");
}

std::pair<std::string, std::string> split_at_existing_directory(const std::string& real) {
  const fs::path path(real);
  const fs::path existing = nearest_existing_directory(path.parent_path());
  return {existing.string(), path.lexically_relative(existing).string()};
}

void check_replaceable(const OutputTarget& target, const std::string& what) {
  if (!target.exists) return;
  if (!target.writable)
    throw OutputError(what + ": is read-only (mode " + octal_mode(target.permissions) +
                      "); make it writable or choose another output");
  if (target.links > 1)
    throw OutputError(what + ": has " + std::to_string(target.links) +
                      " names (hard links); replacing it would leave the other names with the "
                      "old content; expected a file with one name");
}

void check_can_create_beside(const OutputTarget& target, const std::string& what) {
  if (target.kind != OutputTarget::Kind::kFile) return;  // stdout, a device or a pipe
  const fs::path parent = fs::path(target.real).parent_path();
  struct stat st {};
  if (::stat(parent.c_str(), &st) != 0) {
    // A directory still to be created: its nearest existing parent must take one.
    const fs::path dir = nearest_existing_directory(parent);
    const std::string probe = (dir / temporary_name("write-check")).string();
    if (::mkdir(probe.c_str(), 0700) != 0)
      throw OutputError(what + ": cannot create directory '" + parent.string() + "' (" +
                        errno_text(errno) + " in '" + dir.string() + "')");
    ::rmdir(probe.c_str());
    return;
  }
  // Probe with the same kind of file the write will create: a new one beside the target.
  const fs::path dir = parent;
  const std::string probe = (dir / temporary_name("write-check")).string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    throw OutputError(what + ": cannot create a file in '" + dir.string() + "' (" +
                      errno_text(errno) + ")");
  ::close(fd);
  ::unlink(probe.c_str());
}

void write_files_atomically(const std::vector<OutputFile>& files,
                            const StandardOutput& standard_output) {
  std::vector<OutputTarget> targets;
  for (const auto& f : files) {
    targets.push_back(resolve_output(f.path, "cannot write '" + f.path + "'"));
    check_replaceable(targets.back(), "cannot write '" + f.path + "'");
  }
  for (const auto& t : targets)
    if (t.kind == OutputTarget::Kind::kFile)
      remove_stale_temporaries(fs::path(t.real).parent_path());
  // Phase 1: every regular file into its temporary file, in its directory, created when
  // missing. Any failure undoes them all, the directories created included.
  std::vector<std::string> temps(files.size());
  std::vector<fs::path> created;
  const auto remove_temps = [&temps, &created] {
    for (auto& temp : temps)
      if (!temp.empty()) ::unlink(temp.c_str());
    for (auto d = created.rbegin(); d != created.rend(); ++d) ::rmdir(d->c_str());
  };
  try {
    for (std::size_t i = 0; i < files.size(); ++i) {
      if (targets[i].kind != OutputTarget::Kind::kFile) continue;
      const auto made =
          create_missing_directories(fs::path(targets[i].real).parent_path(), files[i].path);
      created.insert(created.end(), made.begin(), made.end());
    }
    for (std::size_t i = 0; i < files.size(); ++i) {
      if (targets[i].kind != OutputTarget::Kind::kFile) continue;
      const fs::path real(targets[i].real);
      const std::string temp =
          (real.parent_path() / temporary_name(real.filename().string())).string();
      write_new_file(temp, files[i].content, targets[i].exists, targets[i].permissions,
                     files[i].path);
      temps[i] = temp;
    }
    // Phase 2: what cannot be replaced, written before anything is: standard output (what
    // the command printed and any output "-") and the devices and FIFOs. A failure there
    // leaves every file as it was, so exit 2 always means "nothing replaced".
    write_standard_output(standard_output, "");
    for (std::size_t i = 0; i < files.size(); ++i) {
      if (targets[i].kind == OutputTarget::Kind::kStdout)
        write_standard_output(standard_output, files[i].content);
      else if (targets[i].kind == OutputTarget::Kind::kStream)
        write_stream(targets[i], files[i].content, standard_output);
    }
  } catch (...) {
    remove_temps();
    throw;
  }
  // Phase 3: the renames, which cannot run out of space, under the locks of their
  // directories: another kincal writing the same files waits, and renames its set after.
  // A single file is locked too: its rename must not land between another writer's two.
  std::vector<std::string> directories;
  for (std::size_t i = 0; i < files.size(); ++i)
    if (!temps[i].empty()) directories.push_back(fs::path(targets[i].real).parent_path().string());
  const RenameLocks locks(directories);
  bool renamed_one = false;
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (temps[i].empty()) continue;
    if (renamed_one) pause_between_renames();
    renamed_one = true;
    if (::rename(temps[i].c_str(), targets[i].real.c_str()) != 0) {
      const int error = errno;
      remove_temps();
      fail_errno(files[i].path, error);
    }
    temps[i].clear();
    write_step();
    sync_directory(fs::path(targets[i].real).parent_path().string());
    write_step();
  }
}

void check_standard_output(const StandardOutput& standard_output) {
  write_standard_output(standard_output, "");
}

// ---- a directory replaced whole --------------------------------------------------------

DirectoryTarget resolve_output_directory(const std::string& path, const std::string& what,
                                         const std::vector<std::string>& owned) {
  DirectoryTarget t;
  t.path = path;
  if (path.empty()) throw OutputError(what + ": empty path, expected a directory");
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  if (ec) throw OutputError(what + ": " + ec.message());
  // Resolve what exists; the rest (a new directory and maybe new parents) is appended.
  fs::path real = fs::weakly_canonical(absolute, ec);
  if (ec) throw OutputError(what + ": " + ec.message());
  if (real.filename().empty()) real = real.parent_path();  // "new/" when "new" does not exist
  t.real = real.string();
  if (!real.has_parent_path() || real == real.root_path())
    throw OutputError(what + ": is the root directory; expected a directory of its own");
  const fs::path cwd = fs::current_path(ec);
  if (!ec) {
    const auto [mismatch, unused] = std::mismatch(real.begin(), real.end(), cwd.begin(), cwd.end());
    if (mismatch == real.end())
      throw OutputError(what +
                        ": is the current directory or one of its parents; reproduce "
                        "replaces the whole directory, expected a directory of its own");
  }
  struct stat st {};
  if (::lstat(real.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) throw OutputError(what + ": exists and is not a directory");
    struct stat parent {};
    if (::stat(real.parent_path().c_str(), &parent) == 0 && parent.st_dev != st.st_dev)
      throw OutputError(what +
                        ": is a mount point, which cannot be replaced; expected a "
                        "directory inside it");
    for (const auto& entry : fs::directory_iterator(real, ec)) {
      const std::string name = entry.path().filename().string();
      bool known = false;
      for (const auto& o : owned) known = known || o == name;
      if (!known || !entry.is_regular_file(ec) || entry.is_symlink(ec)) {
        std::string list;
        for (const auto& o : owned) list += (list.empty() ? "" : ", ") + o;
        throw OutputError(what + ": holds '" + name + "', which is not one of the files this " +
                          "command writes (" + list +
                          "); the whole directory is replaced, so expected a new directory or "
                          "one that only this command wrote");
      }
    }
    if (ec) throw OutputError(what + ": cannot list it (" + ec.message() + ")");
    t.exists = true;
    t.permissions = st.st_mode & 07777;
  }
  // The nearest existing parent must let us create the temporary directory (and parents).
  fs::path parent = real.parent_path();
  while (::stat(parent.c_str(), &st) != 0 && parent.has_parent_path() &&
         parent != parent.root_path())
    parent = parent.parent_path();
  if (!S_ISDIR(st.st_mode))
    throw OutputError(what + ": '" + parent.string() + "' is not a directory");
  const std::string probe = (parent / temporary_name("write-check")).string();
  if (::mkdir(probe.c_str(), 0700) != 0)
    throw OutputError(what + ": cannot create a directory in '" + parent.string() + "' (" +
                      errno_text(errno) + ")");
  ::rmdir(probe.c_str());
  return t;
}

void write_directory_atomically(const DirectoryTarget& target,
                                const std::vector<OutputFile>& files) {
  const fs::path real(target.real);
  const fs::path parent = real.parent_path();
  const std::vector<fs::path> created = create_missing_directories(parent, target.path);
  const auto remove_created = [&created] {
    for (auto d = created.rbegin(); d != created.rend(); ++d) ::rmdir(d->c_str());
  };
  remove_stale_temporaries(parent);
  const fs::path temp = parent / temporary_name(real.filename().string());
  if (::mkdir(temp.c_str(), static_cast<mode_t>(target.exists ? 0700 : 0777)) != 0) {
    const int error = errno;
    remove_created();
    throw OutputError("cannot write '" + target.path + "': cannot create a directory beside it (" +
                      errno_text(error) + ")");
  }
  write_step();
  try {
    for (const auto& f : files)
      write_new_file((temp / f.path).string(), f.content, false, 0, target.path + "/" + f.path);
    if (target.exists && ::chmod(temp.c_str(), static_cast<mode_t>(target.permissions)) != 0)
      fail_errno(target.path, errno);
    sync_directory(temp.string());
    write_step();
    // One step: a crash leaves the old directory or the new one, never a mix.
    const int swapped =
        target.exists ? ::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, real.c_str(), RENAME_EXCHANGE)
                      : ::rename(temp.c_str(), real.c_str());
    if (swapped != 0) {
      const int error = errno;
      if (error == EINVAL && target.exists)
        throw OutputError("cannot write '" + target.path +
                          "': this file system cannot swap directories atomically (no "
                          "RENAME_EXCHANGE); remove the old directory first or choose another");
      fail_errno(target.path, error);
    }
  } catch (...) {
    remove_directory_of_files(temp);
    remove_created();
    throw;
  }
  write_step();
  sync_directory(parent.string());
  write_step();
  if (target.exists) {
    // The old directory now has the temporary name; a crash here leaves it to the next
    // write's clean-up. It held only the files written here (resolve_output_directory).
    for (const auto& f : files) {
      ::unlink((temp / f.path).c_str());
      write_step();
    }
    ::rmdir(temp.c_str());
    write_step();
  }
}

}  // namespace kincal
