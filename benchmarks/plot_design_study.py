#!/usr/bin/env python3
"""Plots and the table of kincal-design-study (docs/experiment-design.md).

usage: plot_design_study.py RESULTS_DIR OUT_DIR
Reads RESULTS_DIR/runs.csv and summary.json; writes OUT_DIR/design-study-errors.svg (the
validation position error per case and variant over seeds, with the nominal model's and the
predicted bound's medians) and OUT_DIR/design-study-predicted.svg (predicted RMS against the
Monte Carlo RMS), and prints the Markdown tables: the results, and each design against the
relaxation bound of design_bound (how far the best possible design of its size could go).
"""
import csv
import json
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

results, out_dir = sys.argv[1], sys.argv[2]
summary = json.load(open(f"{results}/summary.json"))
runs = defaultdict(list)
for row in csv.DictReader(open(f"{results}/runs.csv")):
    runs[(int(row["case"]), row["variant"])].append(row)
cases = sorted({c["case"] for c in summary["cells"]})
variants = []
for c in summary["cells"]:
    if c["variant"] not in variants:
        variants.append(c["variant"])
cell = {(c["case"], c["variant"]): c for c in summary["cells"]}

fig, axes = plt.subplots(1, len(cases), figsize=(4.2 * len(cases), 4.2), sharey=True)
if len(cases) == 1:
    axes = [axes]
for ax, case in zip(axes, cases):
    data = [[float(r["after_mean_mm"]) for r in runs[(case, v)]] for v in variants]
    ax.boxplot(data, whis=(5, 95), showfliers=False)
    ax.set_xticks(range(1, len(variants) + 1), variants, rotation=40, ha="right")
    predicted = [cell[(case, v)]["median_predicted_rms_mm"] for v in variants]
    ax.plot(range(1, len(variants) + 1), predicted, "r_", markersize=18, mew=2,
            label="predicted RMS (median over seeds)")
    before = cell[(case, variants[0])]["median_before_mm"]
    ax.axhline(before, color="gray", ls="--", label="nominal model (median)")
    ax.set_yscale("log")
    ax.set_title(f"case {case}")
    ax.grid(True, which="both", axis="y", alpha=0.3)
axes[0].set_ylabel("validation position error, mean over poses (mm)")
axes[0].legend(fontsize=8)
fig.suptitle(f"{summary['seeds']} seeds per box (whiskers 5-95 %)")
fig.tight_layout()
fig.savefig(f"{out_dir}/design-study-errors.svg")

fig, ax = plt.subplots(figsize=(5, 5))
for case, marker in zip(cases, "os^"):
    xs = [cell[(case, v)]["mc_rms_mm"] for v in variants]
    ys = [cell[(case, v)]["predicted_rms_mm"] for v in variants]
    ax.scatter(xs, ys, marker=marker, label=f"case {case}")
    for v, x, y in zip(variants, xs, ys):
        ax.annotate(v, (x, y), fontsize=6, xytext=(3, -3), textcoords="offset points")
lo = min(min(c["mc_rms_mm"], c["predicted_rms_mm"]) for c in summary["cells"]) / 1.5
hi = max(max(c["mc_rms_mm"], c["predicted_rms_mm"]) for c in summary["cells"]) * 1.5
ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
ax.plot([lo, hi], [1.15 * lo, 1.15 * hi], "k:", lw=0.8)
ax.plot([lo, hi], [lo / 1.15, hi / 1.15], "k:", lw=0.8)
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("Monte Carlo RMS validation position error (mm)")
ax.set_ylabel("predicted RMS (mm)")
ax.legend()
ax.grid(True, which="both", alpha=0.3)
fig.tight_layout()
fig.savefig(f"{out_dir}/design-study-predicted.svg")

print("| case | variant | median error (mm) | vs random | MC RMS (mm) | predicted RMS (mm) | "
      "predicted / MC | worse than nominal |")
print("|---|---|---|---|---|---|---|---|")
for case in cases:
    base = cell[(case, "random")]["median_after_mm"]
    for v in variants:
        c = cell[(case, v)]
        print(f"| {case} | {v} | {c['median_after_mm']:.3g} | {base / c['median_after_mm']:.1f}x | "
              f"{c['mc_rms_mm']:.3g} | {c['predicted_rms_mm']:.3g} | "
              f"{c['predicted_rms_mm'] / c['mc_rms_mm']:.2f} | {c['worse_than_nominal']}/{c['runs']} |")
    print(f"| {case} | nominal model | {cell[(case, 'random')]['median_before_mm']:.3g} | | | | | |")

# How close each design is to the best any design of the same size from the same candidates
# can be (the relaxation's bound, design_bound in framework/design/experiment_design.hpp).
print()
print("| case | variant | design's criterion | bound (no design does better) | "
      "std ratio to the bound |")
print("|---|---|---|---|---|")
for case in cases:
    for v in variants:
        c = cell[(case, v)]
        if "design_criterion_bound" not in c:
            continue
        print(f"| {case} | {v} | {c['design_criterion']:.6g} | {c['design_criterion_bound']:.6g} | "
              f"{c['design_std_ratio_to_bound']:.4f} |")
