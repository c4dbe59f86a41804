#pragma once
// What `kincal fk` and `kincal ik` share: the pose convention they print, and their table
// mode (a file of actuator values or poses in, a table of results out).

#include <functional>
#include <string>
#include <vector>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/workflows/kinematics_rows.hpp"

namespace kincal::cli {

inline constexpr const char* kPoseConvention =
    "pose = x,y,z,rx,ry,rz: position of the platform frame in the base frame (mm) and Z-Y-X "
    "Euler angles in degrees, R = Rz(rz) Ry(ry) Rx(rx) (rotate about x, then y, then z, all "
    "fixed base axes); a platform point p is at R p + t in the base frame";

/// Adds --out (the table as CSV) and --json for the table mode.
void add_table_outputs(po::options_description& options);

/// Table mode: reads `columns` from `input_file` (a CSV as the measurement files: header,
/// other columns ignored with a note, the model's reading columns silently), computes a row
/// for each line with `compute`, and writes the table to --out (CSV; standard output unless
/// --json is given) and --json.
/// Returns 0, or 1 when some row failed (each has its status; one line on stderr says how
/// many). `plan` holds the inputs already; the outputs are added and checked here.
int run_table(const std::string& command, const po::variables_map& vm, OutputPlan& plan,
              const MeasurementModel& model, const std::string& input_option,
              const std::vector<std::string>& columns,
              const std::function<KinematicsRow(const MeasurementModel&,
                                                const std::vector<double>&)>& compute);

}  // namespace kincal::cli
