// The urdf-arm preset: a UR5 as `kincal model --urdf` imports it from
// examples/ur5-laser-tracker/ur5.urdf (the same text, kept here so that the preset exports
// into it), with a laser tracker whose reflector sits off joint 6's axis, and the free set a
// calibration would choose: the parameters a default simulation's configurations determine
// (identifiable_subset), the others fixed.

#include <cmath>

#include "kincal/framework/base/angles.hpp"
#include "kincal/models/point_tracker.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "kincal/models/urdf_io.hpp"

namespace kincal {

namespace {

const char* kUr5Urdf = R"urdf(<?xml version="1.0"?>
<!-- Universal Robots UR5 (CB3), written for kincal's example from the kinematic and dynamic
     parameters Universal Robots publishes ("Parameters for calculations of kinematics and
     dynamics", UR5 table):
       DH  d1 = 89.159 mm, a2 = -425 mm, a3 = -392.25 mm, d4 = 109.15 mm, d5 = 94.65 mm,
           d6 = 82.3 mm; alpha = pi/2, 0, 0, pi/2, -pi/2, 0; theta offsets 0
       masses 3.7, 8.393, 2.275, 1.219, 1.219, 0.1879 kg; centres of mass (DH frame i)
           (0, -25.61, 1.93), (212.5, 0, 113.36), (150, 0, 26.5), (0, -1.8, 16.34),
           (0, 1.8, 16.34), (0, 0, -1.159) mm
     Link frames: joint i turns about the z axis of its link's frame; joint i's origin is the
     constant part Tz(d) Tx(a) Rx(alpha) of DH link i-1, so that with all joints at 0 the
     frame of the link after joint i is DH frame i-1 of the published table. The `flange` link is DH frame 6 (z along
     joint 6's axis, on the tool flange's face). The centres of mass are those of the table
     moved into these link frames. UR publishes no inertia tensors: the ones below are a
     solid sphere of 5 cm radius with the link's mass (2/5 m r^2), a placeholder for
     dynamics, irrelevant to kinematic calibration. Limits: +-2 pi, UR5 joint torques and
     speeds from the same manual. -->
<robot name="ur5">
  <link name="base_link">
    <visual>
      <geometry><cylinder radius="0.075" length="0.05"/></geometry>
    </visual>
  </link>

  <joint name="shoulder_pan_joint" type="revolute">
    <parent link="base_link"/>
    <child link="shoulder_link"/>
    <origin xyz="0 0 0" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-6.283185307179586" upper="6.283185307179586" effort="150" velocity="3.15"/>
  </joint>
  <link name="shoulder_link">
    <inertial>
      <origin xyz="0 -0.00193 0.063549" rpy="0 0 0"/>
      <mass value="3.7"/>
      <inertia ixx="0.0037" ixy="0" ixz="0" iyy="0.0037" iyz="0" izz="0.0037"/>
    </inertial>
    <visual>
      <origin xyz="0 0 0.0446" rpy="0 0 0"/>
      <geometry><cylinder radius="0.06" length="0.09"/></geometry>
    </visual>
  </link>

  <joint name="shoulder_lift_joint" type="revolute">
    <parent link="shoulder_link"/>
    <child link="upper_arm_link"/>
    <origin xyz="0 0 0.089159" rpy="1.5707963267948966 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-6.283185307179586" upper="6.283185307179586" effort="150" velocity="3.15"/>
  </joint>
  <link name="upper_arm_link">
    <inertial>
      <origin xyz="-0.2125 0 0.11336" rpy="0 0 0"/>
      <mass value="8.393"/>
      <inertia ixx="0.0083930" ixy="0" ixz="0" iyy="0.0083930" iyz="0" izz="0.0083930"/>
    </inertial>
    <visual>
      <origin xyz="-0.2125 0 0.136" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.05" length="0.425"/></geometry>
    </visual>
  </link>

  <joint name="elbow_joint" type="revolute">
    <parent link="upper_arm_link"/>
    <child link="forearm_link"/>
    <origin xyz="-0.425 0 0" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3.141592653589793" upper="3.141592653589793" effort="150" velocity="3.15"/>
  </joint>
  <link name="forearm_link">
    <inertial>
      <origin xyz="-0.24225 0 0.0265" rpy="0 0 0"/>
      <mass value="2.275"/>
      <inertia ixx="0.002275" ixy="0" ixz="0" iyy="0.002275" iyz="0" izz="0.002275"/>
    </inertial>
    <visual>
      <origin xyz="-0.196125 0 0.0165" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.04" length="0.39225"/></geometry>
    </visual>
  </link>

  <joint name="wrist_1_joint" type="revolute">
    <parent link="forearm_link"/>
    <child link="wrist_1_link"/>
    <origin xyz="-0.39225 0 0" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-6.283185307179586" upper="6.283185307179586" effort="28" velocity="3.2"/>
  </joint>
  <link name="wrist_1_link">
    <inertial>
      <origin xyz="0 -0.01634 0.10735" rpy="0 0 0"/>
      <mass value="1.219"/>
      <inertia ixx="0.001219" ixy="0" ixz="0" iyy="0.001219" iyz="0" izz="0.001219"/>
    </inertial>
  </link>

  <joint name="wrist_2_joint" type="revolute">
    <parent link="wrist_1_link"/>
    <child link="wrist_2_link"/>
    <origin xyz="0 0 0.10915" rpy="1.5707963267948966 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-6.283185307179586" upper="6.283185307179586" effort="28" velocity="3.2"/>
  </joint>
  <link name="wrist_2_link">
    <inertial>
      <origin xyz="0 0.01634 0.09285" rpy="0 0 0"/>
      <mass value="1.219"/>
      <inertia ixx="0.001219" ixy="0" ixz="0" iyy="0.001219" iyz="0" izz="0.001219"/>
    </inertial>
  </link>

  <joint name="wrist_3_joint" type="revolute">
    <parent link="wrist_2_link"/>
    <child link="wrist_3_link"/>
    <origin xyz="0 0 0.09465" rpy="-1.5707963267948966 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-6.283185307179586" upper="6.283185307179586" effort="28" velocity="3.2"/>
  </joint>
  <link name="wrist_3_link">
    <inertial>
      <origin xyz="0 0 0.081141" rpy="0 0 0"/>
      <mass value="0.1879"/>
      <inertia ixx="0.0001879" ixy="0" ixz="0" iyy="0.0001879" iyz="0" izz="0.0001879"/>
    </inertial>
  </link>

  <!-- DH frame 6: the tool flange's face, z along joint 6's axis. -->
  <joint name="flange_joint" type="fixed">
    <parent link="wrist_3_link"/>
    <child link="flange"/>
    <origin xyz="0 0 0.0823" rpy="0 0 0"/>
  </joint>
  <link name="flange"/>
</robot>
)urdf";

UrdfArmJoint revolute(const std::string& name, double x, double y, double z, double rx,
                      double limit, double home_deg) {
  UrdfArmJoint j;
  j.name = name;
  j.type = UrdfJointType::kRevolute;
  j.origin << x, y, z, rx, 0, 0;
  j.axis = Vector3d::UnitZ();
  j.lower = -limit;
  j.upper = limit;
  j.home = home_deg * kPi / 180;
  return j;
}

}  // namespace

std::string ur5_urdf_text() { return kUr5Urdf; }

std::string ur5_urdf_description() {
  return "Universal Robots UR5 imported from a URDF written from UR's published DH parameters "
         "and masses (examples/ur5-laser-tracker/ur5.urdf): per joint a 6-DOF origin error and "
         "an offset; a laser tracker with the reflector off joint 6's axis; home with elbow and "
         "wrist 90 degrees from their singularities; free: the 27 parameters 30 configurations "
         "around home determine (QR with column pivoting), the other 36 fixed";
}

namespace {

UrdfArmGeometry ur5_geometry() {
  UrdfArmGeometry g;
  g.urdf_file = "ur5.urdf";
  g.urdf_text = kUr5Urdf;
  g.base_link = "base_link";
  g.tip_link = "flange";
  const double two_pi = 2 * kPi;
  g.joints = {revolute("shoulder_pan_joint", 0, 0, 0, 0, two_pi, 0),
              revolute("shoulder_lift_joint", 0, 0, 89.159, kPi / 2, two_pi, -90),
              revolute("elbow_joint", -425, 0, 0, 0, kPi, 90),
              revolute("wrist_1_joint", -392.25, 0, 0, 0, two_pi, -90),
              revolute("wrist_2_joint", 0, 0, 109.15, kPi / 2, two_pi, -90),
              revolute("wrist_3_joint", 0, 0, 94.65, -kPi / 2, two_pi, 0)};
  g.tip << 0, 0, 82.3, 0, 0, 0;
  return g;
}

}  // namespace

std::shared_ptr<MeasurementModel> make_ur5_urdf() {
  auto arm = std::make_shared<UrdfArm>(ur5_geometry());
  auto tracker = std::make_shared<PointTracker>("tracker", Vector6d::Zero(), Vector3d(40, 30, 50));
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{tracker});
  // The identification Jacobian at nominal on 30 fixed configurations spread over the default
  // box around home; the parameters its pivoted QR keeps are the free set.
  free_what_home_configurations_determine(*model, 1.7, 2.3, 0.1);
  return model;
}

std::string ur5_urdf_compliance_description() {
  return "the UR5 of ur5-urdf with joint compliance under gravity: its URDF's masses (UR's "
         "published masses and centres), 1e-5 rad/Nm per joint, a payload of 0 to 5 kg 50 mm "
         "beyond the flange read per row (column payload, kg); free: what 30 configurations "
         "around home determine";
}

std::shared_ptr<MeasurementModel> make_ur5_urdf_compliance() {
  UrdfArmGeometry g = ur5_geometry();
  g.compliance = import_urdf(kUr5Urdf, "ur5.urdf", "base_link", "flange").compliance;
  g.compliance.enabled = true;
  g.compliance.payload_column = true;
  g.compliance.payload_max = 5.0;
  g.compliance.payload.centre = Vector3d(0, 0, 50);
  for (const UrdfArmJoint& j : g.joints)
    g.compliance.values.emplace_back(j.name + ".compliance", 1e-5);
  auto arm = std::make_shared<UrdfArm>(g);
  auto tracker = std::make_shared<PointTracker>("tracker", Vector6d::Zero(), Vector3d(40, 30, 50));
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{tracker});
  free_what_home_configurations_determine(*model, 1.7, 2.3, 0.1);
  return model;
}

}  // namespace kincal
