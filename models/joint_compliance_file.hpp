#pragma once
// The "compliance" section of a serial chain's mechanism in model files (the urdf-arm's and
// the serial-arm's; models/joint_compliance.hpp):
//
//   "compliance": {
//     "masses": "given",              "given" (the links below) or "fitted" (their products
//                                     with the compliances are parameters)
//     "masses_source": "URDF inertials",   optional, for reports
//     "links": [ { "mass_kg": 3.7, "centre": [x, y, z] }, ... ],   "given": one per moving
//                                     joint, what its child link carries, centre in mm in that
//                                     link's frame (a URDF link's; a DH arm's frame i)
//     "gravity": [0, 0, -1],          optional: gravity's direction in the base's frame
//     "payload": { "mass_kg": 0, "centre": [x, y, z], "column": false, "max_kg": 5 },
//                                     optional: the payload (centre in the tip's frame, mm);
//                                     "column": true reads its mass per row from the
//                                     measurement column "payload" (kg), drawn in [0, max_kg]
//     "values": { "shoulder_lift_joint.compliance": 1.2e-5, ... }   optional, zero: the
//                                     compliance parameters' values in their units (rad/Nm,
//                                     mm/N, rad/m, mm; gravity.rx/ry in rad)
//   }

#include <cstddef>

#include "kincal/framework/io/json_fields.hpp"
#include "kincal/models/joint_compliance.hpp"

namespace kincal {

/// The section at `at` for a chain of `joints` moving joints; fails with the key's path.
ComplianceSpec read_compliance(const Json& j, const JsonPath& at, std::size_t joints);
/// The section of `spec` (enabled).
Json compliance_json(const ComplianceSpec& spec);

}  // namespace kincal
