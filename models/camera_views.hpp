#pragma once
// A camera's views as a calibration report shows them (framework/analysis/image_views.hpp):
// per data row with points measured, each point as measured and as the model predicts it at
// the calibrated parameters, and the reprojection error per view and overall.

#include <string>
#include <vector>

#include "kincal/framework/analysis/image_views.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/measurement_loading.hpp"
#include "kincal/models/camera_start.hpp"

namespace kincal {

/// Whether a sensor of `model` is a camera.
bool has_camera(const MeasurementModel& model);

/// The views of the camera that is `sensor_index` of `model` at `params`: one per row of
/// `data` with a point measured, labelled by `labels` (one per row; "row N" where missing)
/// and, when given, named by `images` (one per row). A row whose forward kinematics fails or
/// whose camera does not read there has no predicted points: it is left out.
ImageViews camera_image_views(const MeasurementModel& model, int sensor_index,
                              const Eigen::Ref<const VectorXd>& params, const Measurements& data,
                              const std::vector<std::string>& labels,
                              const std::vector<std::string>& images = {});

/// The image of each data row as the measurement file `data_file` names it in its `image`
/// column (what `kincal detect` writes), one per line of `lines`; empty when the file has no
/// such column. Throws std::invalid_argument when the file cannot be read.
std::vector<std::string> images_of_rows(const std::string& data_file,
                                        const std::vector<int>& lines);

/// What a calibration report adds for the cameras of `model` at `params` (camera_view_checks),
/// for `data` read from `data_file`: rows labelled "<data_file>:<line>" and each view named by
/// the file's `image` column when it has one. Empty without a camera. The program and Python
/// both call it.
CameraViewChecks calibration_camera_views(const MeasurementModel& model,
                                          const Eigen::Ref<const VectorXd>& params,
                                          const LoadedMeasurements& data,
                                          const std::string& data_file);

}  // namespace kincal
