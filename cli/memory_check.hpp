#pragma once
// Counts from the command line (--poses, --trials, --validation) checked against the memory
// the run would need, before any work or output: a count that cannot fit is one clear line,
// not std::bad_alloc after minutes (or an empty output directory).

#include <cstdint>
#include <string>

namespace kincal::cli {

/// Memory this process may still use, in bytes: the smallest of MemAvailable
/// (/proc/meminfo), the cgroup's limit minus its usage, and the address-space and data
/// rlimits. A source that cannot be read is left out; none at all gives the maximum.
std::uint64_t available_memory_bytes();

/// Throws CliError "<what>: needs about X of memory (<how>), more than the Y available;
/// expected at most about <max> <unit>s" when `count` items of `bytes_per_item` each (plus
/// `fixed_bytes`) exceed available_memory_bytes(). `what` names the option and its value
/// ("--poses 2147483647"), `unit` one item ("configuration").
void check_memory(const std::string& what, double count, double bytes_per_item,
                  const std::string& unit, double fixed_bytes = 0);

/// The same for `matrices` dense n x n matrices of doubles held at once (n = `n`, e.g. the
/// free parameters): needs matrices x 8 n^2 bytes (plus `fixed_bytes`); the message names
/// the largest n that fits.
void check_memory_square(const std::string& what, double n, double matrices,
                         const std::string& unit, double fixed_bytes = 0);

/// Bytes of memory a least-squares solve needs per residual row with `parameters` unknowns:
/// the Jacobian, and the copies solvers make of it (measured: lm and ceres about 4
/// Jacobians' worth; 5 with a margin). The identifiability analyses and the covariance work
/// on the Jacobian's n x n triangular factor and copy no rows (issue 37: with 12, for
/// observability's former SVD of the whole Jacobian, a pose tracker's 10^6 rows were
/// refused at 38 GB on a 24 GB machine).
double solve_bytes_per_row(int parameters);

/// Bytes a simulated configuration needs besides the solve: its actuator values, readings and
/// true pose (about 150; with margin).
inline constexpr double kConfigurationBytes = 512;

}  // namespace kincal::cli
