#pragma once
// Small fixed-size Eigen types shared by every layer.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace kincal {

using Vector3d = Eigen::Vector3d;
using Matrix3d = Eigen::Matrix3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix6Xd = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using RowVector6d = Eigen::Matrix<double, 1, 6>;
using MatrixX6d = Eigen::Matrix<double, Eigen::Dynamic, 6>;
using Eigen::MatrixXd;
using Eigen::VectorXd;

}  // namespace kincal
