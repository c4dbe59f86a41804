#pragma once
// What `kincal fk` and `kincal ik` share: the pose convention they print, and their table
// mode (a file of actuator values or poses in, a table of results out).

#include <string>
#include <vector>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/workflows/kinematics_table.hpp"

namespace kincal::cli {

inline constexpr const char* kPoseConvention =
    "pose = x,y,z,rx,ry,rz: position of the platform frame in the base frame (mm) and Z-Y-X "
    "Euler angles in degrees, R = Rz(rz) Ry(ry) Rx(rx) (rotate about x, then y, then z, all "
    "fixed base axes); a platform point p is at R p + t in the base frame";

/// Adds --out (the table as CSV) and --json for the table mode.
void add_table_outputs(po::options_description& options);

/// Table mode: reads --data (`request` says the rest; framework/workflows/kinematics_table.hpp),
/// prints its notes, and writes the table to --out (CSV; standard output unless --json is
/// given) and --json. Returns 0, or 1 when some row failed (each has its status; one line on
/// stderr says how many). `plan` holds the inputs already; the outputs are added and checked
/// here.
int run_table(const std::string& command, const po::variables_map& vm, OutputPlan& plan,
              const MeasurementModel& model, KinematicsTableRequest request);

}  // namespace kincal::cli
