#pragma once
// A gauge freedom the Jacobian does not show: turning the whole setup.
//
// When nothing measured is tied to a frame of its own (sockets: unknown points the tool is put
// into, measured as 0), the measurement frame is arbitrary. Moving the mechanism's base and
// every socket together by a rigid motion leaves every |tool point - socket| and every known
// distance between sockets as they are, so the cost does not change. A shift of the whole
// setup leaves each residual as it is: an exact null direction of the Jacobian, which the
// numerical rank finds. A turn R does not: it turns each socket's residual t - p into
// R (t - p), which the Jacobian sees wherever the tool misses its socket (at the starting
// values, by millimetres), although the cost, a sum of |t - p|^2, does not change. A
// Gauss-Newton analysis would call such a turn determined, by the residuals themselves: its
// scaled singular value is proportional to how far the tool misses its sockets (measured on
// the Panda socket data: 2e-3 of the largest at the start, above genuine parameters at
// 5e-5), so no rank threshold can tell it apart. The turns are therefore given to the
// identifiability analysis explicitly (framework/analysis/identifiability.hpp), which counts
// a turn the free parameters reproduce as a direction the data cannot determine.

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

/// The change of `problem`'s whitened residuals at the free parameters x under turns of the
/// measurement frame about its x, y and z axes (three columns; rows as problem.evaluate gives
/// them, then one zero row per constraint residual, as append_constraint_rows adds them):
/// w x r for the three readings of each sensor whose readings are a vector in the measurement
/// frame (Sensor::frame_vector_reading_index), 0 elsewhere. No columns when a turn is no
/// symmetry of the cost: no such sensor, one of them measured other than 0 (then its readings
/// fix the frame's orientation), or its three readings of unequal reading_std (then the
/// frame's axes weigh differently), or x cannot be evaluated.
MatrixXd measurement_frame_turns(const CalibrationProblem& problem, const VectorXd& x);

}  // namespace kincal
