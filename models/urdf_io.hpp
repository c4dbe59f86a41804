#pragma once
// URDF in and out, through Debian's urdfdom (parsing) and TinyXML (the library urdfdom itself
// reads with; editing the user's document in place):
//   import_urdf    a robot description's chain from a base link to a tip link as a urdf-arm
//                  geometry (models/urdf_arm.hpp)
//   export_urdf_arm  the user's own URDF with the calibrated joint origins and offsets, a
//                  root link `world` (the measurement frame) and a link `tcp` (the measured
//                  point or frame) on the tip
// Each throws UrdfError (models/urdf_xml.hpp) with one sentence on input it cannot take.

#include <memory>
#include <string>

#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "kincal/models/urdf_xml.hpp"

namespace kincal {

/// The moving joints (revolute, continuous, prismatic) from `base_link` (empty: the URDF's
/// root link) down to `tip_link`, fixed joints folded into the next origin; limits kept; home
/// 0 where the limits allow it, else mid-range. Lengths converted to mm. `file` is recorded.
/// Refused, with the line and the element: what scan_urdf_xml refuses, what urdfdom cannot
/// parse, a link with two parent joints, a cycle of joints, a moving joint or the base or tip
/// link whose name breaks the names policy (framework/kinematics/names.hpp), limits with lower
/// above upper or beyond what a model file holds.
UrdfArmGeometry import_urdf(const std::string& text, const std::string& file,
                            const std::string& base_link, const std::string& tip_link);

/// Joint compliance of a model imported from a URDF (models/joint_compliance.hpp): none, the
/// URDF's <inertial> masses when it has them and fitted masses otherwise, the inertials (an
/// error without them), or fitted masses.
enum class UrdfCompliance { kNone, kAuto, kInertials, kFitted };

/// What a model imported from a URDF measures with: one tracker on the tip link.
struct UrdfModelOptions {
  std::string base_link;  ///< empty: the URDF's root link
  std::string tip_link;
  std::string sensor = "point-tracker";  ///< or "pose-tracker"
  Vector3d point = Vector3d::Zero();     ///< the point tracker's target in the tip frame, mm
  /// The tracker's frame in the arm's base coordinates [x, y, z mm, rx, ry, rz rad] (Z-Y-X),
  /// its starting value (identity: the tracker registered to the base).
  Vector6d frame = Vector6d::Zero();
  /// A pose tracker's marker in the tip link's frame [x, y, z mm, rx, ry, rz rad].
  Vector6d target = Vector6d::Zero();
  UrdfCompliance compliance = UrdfCompliance::kNone;
  bool payload_column = false;  ///< the payload's mass per row, column "payload" (kg)
  Vector3d payload_centre = Vector3d::Zero();  ///< in the tip link's frame, mm
};

/// A model of the arm in the URDF `text` (recorded as `file`) with one tracker, every
/// parameter free (calibrate keeps the ones the data determine). Throws UrdfError for what
/// import_urdf refuses, std::invalid_argument for a sensor other than point-tracker or
/// pose-tracker, a point given to a pose tracker, an arm the urdf-arm type refuses, and a
/// model whose file would not read back (over a model file's size, or refused by the reader).
std::shared_ptr<MeasurementModel> model_from_urdf(const std::string& text, const std::string& file,
                                                  const UrdfModelOptions& options);

/// The measured point or frame on the tool and the measurement frame, as the model's sensor
/// sees them: tcp = the tool frame composed with the sensor's target (point tracker) or
/// marker (pose tracker); world = the sensor's frame. Sockets (any number, and no tracker)
/// read the tool frame's origin in the mechanism's base coordinates: tcp = the tool frame,
/// world = those coordinates. Throws UrdfError when the model's sensors do not define one
/// tcp (no tracker nor socket, several trackers, or a tracker and sockets).
struct MeasuredFrames {
  Pose world_from_mechanism;  ///< the mechanism's base coordinates in the measurement frame
  Pose tcp_in_tool;           ///< the measured point or frame in the mechanism's end frame
  std::string sensor;         ///< e.g. "point-tracker 'tracker'"
};
MeasuredFrames measured_frames(const MeasurementModel& model, const VectorXd& values);

/// The URDF of an urdf-arm model with parameter values `values`: its own URDF text, byte for
/// byte, except that every moving joint's origin (its xyz and rpy values) becomes origin *
/// origin_error * motion(offset), a fixed joint from a new root link `world` to the URDF's
/// root and one from the tip link to a new link `tcp` are inserted before </robot>, and
/// `header` (plain text, escaped here) goes into a comment at the top. The result is read
/// back through urdfdom and checked against what was meant before it is returned.
std::string export_urdf_arm(const MeasurementModel& model, const VectorXd& values,
                            const std::string& header);

}  // namespace kincal
