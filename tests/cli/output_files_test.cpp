// How every command writes its output files (write_file_atomically / write_files_atomically,
// cli/cli_util.cpp), exercised through `kincal model --out`, the command that does nothing
// else: symlinks, permission bits, streams, paths that are not files, and writes that fail
// half-way. Every target lives in a fresh temporary directory: never a real device.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_runner.hpp"

namespace kincal {
namespace {

namespace fs = std::filesystem;
using kincal::testing::count_hidden_files;
using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using kincal::testing::with_file_size_limit;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

bool is_model(const std::string& text) {
  const auto j = nlohmann::json::parse(text, nullptr, false);
  return !j.is_discarded() && j.value("format", "") == "kincal-model";
}

TEST(CliOutputFiles, SymlinkWritesItsTargetAndStaysALink) {
  TempDir dir("out-symlink");
  fs::create_directory(dir.path() / "real");
  write(dir / "real/M.json", "old");
  fs::create_symlink("real/M.json", dir.path() / "link.json");
  const auto r = run_cli("model --out " + dir / "link.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir.path() / "link.json"));
  EXPECT_TRUE(is_model(read_text(dir / "real/M.json")));
  // The temporary file went beside the target, and is gone.
  EXPECT_EQ(count_hidden_files(dir.path()), 0);
  EXPECT_EQ(count_hidden_files(dir.path() / "real"), 0);

  // A dangling link creates its target.
  fs::create_symlink("real/new.json", dir.path() / "dangling.json");
  ASSERT_EQ(run_cli("model --out " + dir / "dangling.json").exit_code, 0);
  EXPECT_TRUE(is_model(read_text(dir / "real/new.json")));
}

TEST(CliOutputFiles, PermissionBitsOfTheOldFileAreKept) {
  TempDir dir("out-mode");
  const std::string m = dir / "M.json";
  write(m, "old");
  fs::permissions(m, fs::perms::owner_read | fs::perms::owner_write);  // 600
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  EXPECT_TRUE(is_model(read_text(m)));
  EXPECT_EQ(fs::status(m).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
}

TEST(CliOutputFiles, AFifoIsWrittenDirectlyNotReplaced) {
  TempDir dir("out-fifo");
  const std::string fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = read_text(fifo); });  // open blocks until kincal writes
  const auto r = run_cli("model --out " + fifo);
  // Had kincal never opened the FIFO, this releases the reader instead of hanging.
  const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
  if (fd >= 0) ::close(fd);
  reader.join();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(is_model(received));
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST(CliOutputFiles, ADirectoryIsRefusedAndLeftAlone) {
  TempDir dir("out-dir");
  fs::create_directory(dir.path() / "D");
  write(dir / "D/keep.txt", "keep");
  for (const std::string& target : {dir / "D", dir / "D/", dir / "D/."}) {
    const auto r = run_cli("model --out " + target);
    EXPECT_EQ(r.exit_code, 2) << target;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("directory, expected a file path"), std::string::npos) << r.err;
  }
  EXPECT_EQ(read_text(dir / "D/keep.txt"), "keep");
  EXPECT_EQ(count_hidden_files(dir.path()), 0);
  EXPECT_EQ(count_hidden_files(dir.path() / "D"), 0);
}

// A missing directory is created (the rule for every output, consistency_test.cpp); a path
// through a file or a broken link cannot be.
TEST(CliOutputFiles, PathThroughAFileBrokenLinkAndSymlinkLoopAreOneLine) {
  TempDir dir("out-missing");
  fs::create_symlink("b", dir.path() / "a");
  fs::create_symlink("a", dir.path() / "b");
  fs::create_symlink("nowhere", dir.path() / "dangling");
  write(dir / "f", "a file");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {dir / "f/M.json", "'" + dir / "f" + "' is not a directory"},
      {dir / "f/new/M.json", "'" + dir / "f" + "' is not a directory"},
      {dir / "dangling/M.json", "'" + dir / "dangling" + "' is a broken symbolic link"},
      {dir / "a", "too many levels of symbolic links"},
  };
  for (const auto& [target, expected] : cases) {
    const auto r = run_cli("model --out " + target);
    EXPECT_EQ(r.exit_code, 2) << target;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--out '" + target + "': " + expected), std::string::npos) << r.err;
  }
}

// The write itself fails once under way (the file would exceed the size limit): the old
// file is untouched and the temporary file is removed. Without the limit the same command
// succeeds, so the failure is the limit's.
TEST(CliOutputFiles, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  TempDir dir("out-efbig");
  const std::string m = dir / "M.json";
  write(m, "precious");
  const auto r = run_cli("model --out " + m, with_file_size_limit(1));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("cannot write '" + m + "': File too large"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(m), "precious");
  EXPECT_EQ(count_hidden_files(dir.path()), 0);
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  EXPECT_TRUE(is_model(read_text(m)));
}

}  // namespace
}  // namespace kincal
