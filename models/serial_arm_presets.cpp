#include "kincal/models/serial_arm_presets.hpp"

#include "kincal/models/point_tracker.hpp"
#include "kincal/models/pose_tracker.hpp"
#include "kincal/models/serial_arm.hpp"

namespace kincal {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

SerialJoint dh(const std::string& name, double a, double alpha_deg, double d, double home_deg) {
  SerialJoint j;
  j.name = name;
  j.a = a;
  j.alpha = alpha_deg * kDeg;
  j.d = d;
  j.home = home_deg * kDeg;
  return j;
}

// A link between parallel axes: DH's d is 0 in the published tables and becomes Hayati's
// beta = 0.
SerialJoint hayati(const std::string& name, double a, double alpha_deg, double home_deg) {
  SerialJoint j = dh(name, a, alpha_deg, 0.0, home_deg);
  j.convention = LinkConvention::kHayati;
  return j;
}

// Frame parameters from a position (mm) and Z-Y-X angles rx, ry, rz in degrees, as a model
// file writes them.
Vector6d frame(const Vector3d& position, const Vector3d& rotation_zyx_deg) {
  Vector6d p;
  p << position, rotation_zyx_deg * kDeg;
  return p;
}

// The free mask shared by both presets: everything between the tracker and the end effector
// that the readings can tell apart. Fixed, because another parameter absorbs them:
//   base.*                       the tracker frame (both place the arm in the tracker)
//   joint1.d, joint1.theta       the tracker frame (a slide along and a turn about joint 1's
//                                axis before the joint moves)
//   joint6.*                     the target or marker on the end effector
//   tool.*                       the target or marker (and, for a point, its orientation is
//                                unseen)
void free_identifiable(MeasurementModel& model, const std::string& sensor,
                       const std::string& end_effector_block) {
  ParameterSet& p = model.parameters();
  p.set_free(sensor + ".frame.*", true);
  p.set_free("joint1.a", true);
  p.set_free("joint1.alpha", true);
  for (int i = 2; i <= 5; ++i) p.set_free("joint" + std::to_string(i) + ".*", true);
  p.set_free(sensor + "." + end_effector_block + ".*", true);
}

}  // namespace

std::string puma560_description() {
  return "Unimation PUMA 560: standard DH table of Corke & Armstrong-Helouvry, 'A search for "
         "consensus among model parameters reported for the PUMA 560 robot' (ICRA 1994), as "
         "in Corke's Robotics Toolbox mdl_puma560 (d1 = 0), a Hayati link for the parallel "
         "joints 2-3, home at the toolbox's non-singular pose qn; a laser tracker (point "
         "target); 27 free parameters (4 per joint + 6 - 3 for position only)";
}

std::shared_ptr<MeasurementModel> make_puma560() {
  SerialArmGeometry g;
  g.joints = {dh("joint1", 0, 90, 0, 0),
              hayati("joint2", 431.8, 0, 45),
              dh("joint3", 20.3, -90, 150.05, 180),
              dh("joint4", 0, 90, 431.8, 0),
              dh("joint5", 0, -90, 0, 45),
              dh("joint6", 0, 0, 0, 0)};
  auto arm = std::make_shared<SerialArm>(g);
  // A tracker 2 m in front of the arm, turned towards it; a target 60/40/120 mm off the
  // flange centre (off joint 6's axis, so that joint 6's motion shows in the readings).
  auto tracker = std::make_shared<PointTracker>(
      "tracker", frame(Vector3d(2000, 600, 300), Vector3d(0, 0, 160)), Vector3d(60, 40, 120));
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{tracker});
  free_identifiable(*model, "tracker", "target");
  return model;
}

std::string ur5_description() {
  return "Universal Robots UR5 (CB3): the DH parameters Universal Robots publishes ('Parameters "
         "for calculations of kinematics and dynamics'; CB3 manual, UR5 table), Hayati links "
         "for the parallel joints 2-3-4, home with elbow and wrist 90 degrees from their "
         "singularities; an optical tracker (pose of a marker); 30 free parameters (4 per "
         "joint + 6)";
}

std::shared_ptr<MeasurementModel> make_ur5() {
  SerialArmGeometry g;
  g.joints = {dh("joint1", 0, 90, 89.159, 0),   hayati("joint2", -425, 0, -90),
              hayati("joint3", -392.25, 0, 90), dh("joint4", 0, 90, 109.15, -90),
              dh("joint5", 0, -90, 94.65, -90), dh("joint6", 0, 0, 82.3, 0)};
  auto arm = std::make_shared<SerialArm>(g);
  auto camera = std::make_shared<PoseTracker>(
      "camera", frame(Vector3d(1500, -1200, 900), Vector3d(-100, 15, 120)),
      frame(Vector3d(30, -40, 50), Vector3d(10, -20, 30)));
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{camera});
  free_identifiable(*model, "camera", "marker");
  return model;
}

}  // namespace kincal
