"""A UR5 with a laser tracker (examples/ur5-laser-tracker, docs/calibrating-a-serial-arm.md)
from Python: import the URDF, calibrate from measurements, check on held-out poses, export.
Usage: calibrate_ur5.py [GRID.csv HELDOUT.csv]; without files, it simulates both."""

import os
import sys
import tempfile

import numpy as np

import kincal

here = os.path.dirname(os.path.abspath(__file__))
urdf = os.path.join(here, "..", "ur5-laser-tracker", "ur5.urdf")
model = kincal.model_from_urdf(urdf, tip="flange", sensor="point-tracker")
print(model, "| actuators:", ", ".join(model.actuator_names))

work = tempfile.mkdtemp(prefix="kincal-ur5-")
if len(sys.argv) == 3:
    grid, heldout = sys.argv[1], sys.argv[2]
else:  # a simulated tracker: noise of std 0.006 mm, errors of up to 0.5 mm and 0.002 rad
    grid, heldout = os.path.join(work, "grid.csv"), os.path.join(work, "heldout.csv")
    kincal.simulate(model=model, poses=120, noise_std="0.006mm", param_error="0.5mm,0.002rad", seed=4,
                    write_data=grid, allow_rank_deficient=True)
    kincal.simulate(model=model, poses=40, noise_std="0.006mm", seed=5, truth=grid.replace(".csv", ".truth.json"),
                    write_data=heldout, allow_rank_deficient=True)

data = kincal.Measurements.read(grid, model)
print(f"{len(data)} configurations, readings {data.reading_names}")
report = kincal.calibrate(model, data, allow_rank_deficient=True)
print(f"calibrate: {report.termination}, residual rms {report.residual_rms:.4f} mm, "
      f"{len(report.fixed_by_identifiability)} parameters fixed by identifiability")
check = kincal.validate(report.calibrated_model, heldout)
print("validate:", {k: check[k] for k in check.keys() if k.startswith("position")})
urdf_text = kincal.export(report.calibrated_model, "urdf")
print(f"exported URDF: {len(urdf_text)} characters")
estimate = np.asarray(report.parameters.estimate)
assert np.isfinite(estimate).all()
