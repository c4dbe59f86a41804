#pragma once
// How kincal writes files, for the program and the Python module alike: through temporary
// files (and, for a directory, a temporary directory) beside the target, flushed to disk and
// renamed into place. The program's commands do not call these directly but through
// OutputPlan (output_plan.hpp), which first checks that no output is an input or another
// output. docs/reliability.md states what holds after a crash.
//
// Temporary names are ".<target name>.kincal-tmp-<pid>-<random>", in the target's
// directory. A write first removes such names whose process no longer runs (a write killed
// half-way), so they do not pile up.

#include <sys/types.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kincal/framework/io/standard_output.hpp"

namespace kincal {

/// An output that cannot be written, or may not be: one line naming it and why ("--out
/// 'C.json': is a directory, expected a file path"). The program exits with 2 on it, as on
/// any bad input; Python raises a ValueError.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where an output path really leads. Symbolic links are followed, so a link to a file
/// writes that file and stays a link.
struct OutputTarget {
  enum class Kind {
    kStdout,  ///< "-"
    kFile,    ///< a regular file, existing or new: replaced through a temporary file
    kStream,  ///< a character device or FIFO (/dev/null, a terminal, a pipe, /dev/stdout
              ///< and other /proc/self/fd links): written directly, it cannot be replaced
  };
  Kind kind = Kind::kFile;
  std::string path;             ///< as given, for messages
  std::string real;             ///< symbolic links resolved (the directory made absolute)
  bool exists = false;          ///< kFile: the file is there already
  unsigned permissions = 0666;  ///< kFile: mode bits of the existing file
  unsigned long links = 1;      ///< kFile: names (hard links) of the existing file
  bool writable = true;         ///< kFile: the existing file may be written (a write bit set,
                                ///< and this user may write it)
};

/// Resolves `path`. A missing directory on the way is fine: it is created (with its missing
/// parents) when the file is written, as for every output. Throws OutputError "<what>: <reason>"
/// when it names a directory, another kind of special file (block device, socket), a path
/// through a file or a broken symbolic link, or a symlink loop;
/// `what` names the path in the message (e.g. "--out 'C.json'" or "cannot write 'C.json'").
OutputTarget resolve_output(const std::string& path, const std::string& what);

/// Throws OutputError "<what>: is read-only ..." or "<what>: has N names (hard links) ..." when
/// `target` is an existing file kincal does not replace: one its owner made read-only (a
/// rename would replace it regardless), or one with several names (a rename would give the
/// new content to this name only). docs/reliability.md.
void check_replaceable(const OutputTarget& target, const std::string& what);

/// Throws OutputError "<what>: cannot create a file in '<dir>' (...)" when a new file cannot be
/// created beside `target` (a read-only directory), or its missing directory cannot be
/// created: checked before long work.
void check_can_create_beside(const OutputTarget& target, const std::string& what);

/// `real` (absolute) split into its nearest existing directory and the rest below it
/// ("/a/new/dir/f.json" -> "/a", "new/dir/f.json"), for telling two new files apart.
std::pair<std::string, std::string> split_at_existing_directory(const std::string& real);

/// One file to write.
struct OutputFile {
  std::string path;
  std::string content;
};

/// Writes every file or none, as long as the process runs: each regular file goes to a
/// temporary file beside its real target (same directory, so the rename is atomic), is
/// flushed to disk and takes over the old file's permission bits; only when all of them are
/// written are they renamed over their targets, in the order given. A failure removes the
/// temporary files and leaves every existing file as it was. A crash (kill -9, power loss)
/// between two renames leaves the first ones new and the others old, each file whole.
/// Standard output (what the command printed so far, then any "-" output) and the other
/// streams (kStream) are written after the temporary files and before any rename, so that a
/// stream that fails (a full disk, a closed standard output) leaves every file as it was.
/// An existing file that is read-only (no write bit) or has several names (hard links) is
/// refused by resolve_output. The renames hold an exclusive flock on each target directory
/// (taken in a fixed order, released at the end): two kincal processes writing the same files
/// rename their sets one after the other, so the files left all come from one of them.
/// Standard output is `standard_output`. Throws OutputError "cannot write '<path>': <reason>".
void write_files_atomically(const std::vector<OutputFile>& files,
                            const StandardOutput& standard_output);

/// Flushes what the caller printed on `standard_output` and throws OutputError "cannot write
/// standard output: <reason>" when it could not be written (a full disk, a closed stream).
void check_standard_output(const StandardOutput& standard_output);

/// A directory that a command owns and replaces whole (reproduce --out).
struct DirectoryTarget {
  std::string path;  ///< as given
  std::string real;  ///< absolute, symbolic links resolved
  bool exists = false;
  unsigned permissions = 0777;  ///< of the existing directory
};

/// Resolves `path` as a directory that may hold only the files named in `owned` (and is
/// replaced whole): throws OutputError "<what>: <reason>" when it is not a directory, holds
/// anything else, is the current directory or one of its parents, or is a mount point.
/// A missing directory is fine (its parents are created when written); its nearest
/// existing parent must allow creating a directory.
DirectoryTarget resolve_output_directory(const std::string& path, const std::string& what,
                                         const std::vector<std::string>& owned);

/// Replaces directory `target` by one holding exactly `files` (names without a directory),
/// atomically even under a crash: the files are written and flushed into a new temporary
/// directory beside it, which is then swapped with the old one in one step (Linux
/// renameat2 RENAME_EXCHANGE) or renamed to it when there was none; the old one is removed
/// afterwards. On a file system without RENAME_EXCHANGE it fails and changes nothing.
void write_directory_atomically(const DirectoryTarget& target,
                                const std::vector<OutputFile>& files);

// Two test hooks, read from the environment (without them, nothing happens):
// - KINCAL_TEST_PAUSE_BETWEEN_RENAMES_MS=N: write_files_atomically sleeps N milliseconds (at
//   most 10 s) between two renames, a window in which another process may write the same
//   files (the concurrency test, tests/cli/audit3/plugins.sh);
// - KINCAL_TEST_KILL_AT_WRITE_STEP=N: the process kills itself with SIGKILL at the N-th step
//   of writing files, each creation, write, flush, rename and removal being a step (the
//   crash tests, tests/cli/crash_test.cpp).

}  // namespace kincal
