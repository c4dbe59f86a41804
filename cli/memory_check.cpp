#include "kincal/cli/memory_check.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "kincal/cli/commands.hpp"

namespace kincal::cli {

namespace {

constexpr std::uint64_t kUnlimited = std::numeric_limits<std::uint64_t>::max();

// "MemAvailable:   23456789 kB" in /proc/meminfo.
std::uint64_t meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  std::uint64_t value = 0;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return value * 1024;
  }
  return kUnlimited;
}

// cgroup v2: memory.max ("max" or bytes) minus memory.current, of this process's cgroup.
std::uint64_t cgroup_available() {
  std::ifstream self("/proc/self/cgroup");
  std::string line, group;
  while (std::getline(self, line))
    if (line.rfind("0::", 0) == 0) group = line.substr(3);
  if (group.empty()) return kUnlimited;
  const std::string dir = "/sys/fs/cgroup" + group;
  std::ifstream max_file(dir + "/memory.max"), current_file(dir + "/memory.current");
  std::string max_text;
  std::uint64_t current = 0;
  if (!(max_file >> max_text) || max_text == "max" || !(current_file >> current)) return kUnlimited;
  if (max_text.find_first_not_of("0123456789") != std::string::npos) return kUnlimited;
  const std::uint64_t max = std::stoull(max_text);
  return max > current ? max - current : 0;
}

std::uint64_t rlimit_bytes(int resource) {
  rlimit limit{};
  if (::getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return kUnlimited;
  return static_cast<std::uint64_t>(limit.rlim_cur);
}

std::string human_bytes(double bytes) {
  const char* units[] = {"bytes", "KB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) bytes /= 1000, ++u;
  char text[32];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return text;
}

}  // namespace

std::uint64_t available_memory_bytes() {
  return std::min({meminfo_available(), cgroup_available(), rlimit_bytes(RLIMIT_AS),
                   rlimit_bytes(RLIMIT_DATA)});
}

void check_memory(const std::string& what, double count, double bytes_per_item,
                  const std::string& unit, double fixed_bytes) {
  const double needed = fixed_bytes + count * bytes_per_item;
  const double available = static_cast<double>(available_memory_bytes());
  if (needed <= available) return;
  const double most = std::max(0.0, std::floor((available - fixed_bytes) / bytes_per_item));
  char most_text[32];
  std::snprintf(most_text, sizeof most_text, "%.0f", most);
  throw CliError(what + ": needs about " + human_bytes(needed) + " of memory (" +
                 human_bytes(bytes_per_item) + " per " + unit + "), more than the " +
                 human_bytes(available) + " available; expected at most about " + most_text + " " +
                 unit + "s");
}

void check_memory_square(const std::string& what, double n, double matrices,
                         const std::string& unit, double fixed_bytes) {
  const double per_entry = 8.0 * matrices;
  const double needed = fixed_bytes + per_entry * n * n;
  const double available = static_cast<double>(available_memory_bytes());
  if (needed <= available) return;
  const double most = std::floor(std::sqrt(std::max(0.0, available - fixed_bytes) / per_entry));
  char most_text[32], matrices_text[32];
  std::snprintf(most_text, sizeof most_text, "%.0f", most);
  std::snprintf(matrices_text, sizeof matrices_text, "%.0f", matrices);
  throw CliError(what + ": needs about " + human_bytes(needed) + " of memory (" + matrices_text +
                 " matrices of " + unit + "s x " + unit + "s), more than the " +
                 human_bytes(available) + " available; expected at most about " + most_text + " " +
                 unit + "s");
}

double solve_bytes_per_row(int parameters) { return 5.0 * 8.0 * std::max(parameters, 1); }

}  // namespace kincal::cli
