"""The paper's Monte Carlo from Python, with its figure: position error before and after
calibration per case (docs/python.md). Usage: paper_study.py [TRIALS] [FIGURE.png]"""

import sys

import matplotlib

matplotlib.use("Agg")  # files, not windows: this also runs in CI
import matplotlib.pyplot as plt

import kincal.studies

trials = int(sys.argv[1]) if len(sys.argv) > 1 else 100
figure = sys.argv[2] if len(sys.argv) > 2 else "paper-study.png"

doc = kincal.studies.reproduce(trials=trials)
cases = [c["case"] for c in doc["cases"]]
before = [c["position_before_median_mm"] for c in doc["cases"]]
after = [c["position_after_median_mm"] for c in doc["cases"]]

fig, ax = plt.subplots(figsize=(5, 3))
ax.bar([c - 0.2 for c in cases], before, width=0.4, label="nominal geometry")
ax.bar([c + 0.2 for c in cases], after, width=0.4, label="calibrated")
ax.set(xlabel="case (paper's Table 2)", ylabel="median position error (mm)", yscale="log")
ax.legend()
fig.tight_layout()
fig.savefig(figure)
for c, b, a in zip(cases, before, after):
    print(f"case {c}: {b:.3f} mm -> {a:.4f} mm")
