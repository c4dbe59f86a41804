#!/usr/bin/env python3
"""Plots of the accuracy study and the micro-benchmarks (matplotlib, Agg backend, no other deps).

usage: plot_results.py RESULTS_DIR IMAGE_DIR

RESULTS_DIR holds what kincal-accuracy-study wrote (summary.csv, traces.csv, bounds.csv) and
micro.json from kincal-micro-benchmarks --benchmark_out. Writes PNGs to IMAGE_DIR and
micro.md (the micro-benchmark table) to RESULTS_DIR.
"""

import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator  # noqa: E402

PAPER_FIGURES = {"paper_fig3_cases_1-3.png": ["1", "2", "3"],
                 "paper_fig4_cases_3-5.png": ["3", "4", "5"]}
CASE_COLORS = {"1": "tab:blue", "2": "tab:orange", "3": "tab:green", "4": "tab:red",
               "5": "tab:purple", "3e20": "tab:brown", "m300": "tab:gray"}
MARKERS = "osD^v<>pXh*P"


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return math.nan
    return value


def plain_log_ticks(axis):
    """Log axis labelled 0.5, 1, 2 ... rather than 5x10^-1 (narrow ranges get minor labels)."""
    label = FuncFormatter(lambda v, _: f"{v:g}")
    axis.set_major_formatter(label)
    low, high = axis.get_view_interval()
    if high / max(low, 1e-300) < 30:
        axis.set_minor_locator(LogLocator(subs=(2, 3, 5)))
        axis.set_minor_formatter(label)


def solver_style(solvers):
    cmap = plt.get_cmap("tab10")
    return {s: (cmap(i % 10), MARKERS[i % len(MARKERS)]) for i, s in enumerate(solvers)}


def plot_paper_figures(traces, image_dir):
    """Validation position/orientation error vs iteration: median over seeds, IQR band."""
    tracked = sorted({r["solver"] for r in traces}, key=lambda s: (s != "lm", s))
    written = []
    for filename, cases in PAPER_FIGURES.items():
        fig, axes = plt.subplots(2, len(tracked), figsize=(5.2 * len(tracked), 7.5),
                                 sharex="col", squeeze=False)
        for col, solver in enumerate(tracked):
            # Up to the iteration where 90 % of the trials have stopped, and at most twice the
            # longest median run: the rest is flat (or, for the few gn runs that reach the
            # iteration limit, a two-cycle).
            shown = [r for r in traces if r["solver"] == solver and r["case"] in cases]
            last = max([int(r["iteration"]) for r in shown
                        if int(r["running"]) >= 0.1 * int(r["trials"])], default=0)
            half = max([int(r["iteration"]) for r in shown
                        if int(r["running"]) >= 0.5 * int(r["trials"])], default=0)
            last = min(last, 2 * half + 2)
            for row, (quantity, unit, scale) in enumerate(
                    [("position", "mm", 1.0), ("orientation", "rad", 1.0)]):
                ax = axes[row][col]
                suffix = "mm" if quantity == "position" else "rad"
                for case in cases:
                    rows = [r for r in shown
                            if r["case"] == case and int(r["iteration"]) <= last + 1]
                    if not rows:
                        continue
                    it = [int(r["iteration"]) for r in rows]
                    med = [scale * number(r[f"{quantity}_median_{suffix}"]) for r in rows]
                    lo = [scale * number(r[f"{quantity}_p25_{suffix}"]) for r in rows]
                    hi = [scale * number(r[f"{quantity}_p75_{suffix}"]) for r in rows]
                    color = CASE_COLORS.get(case, "black")
                    ax.plot(it, med, "-o", ms=3, color=color, label=f"case {case}")
                    ax.fill_between(it, lo, hi, color=color, alpha=0.2, lw=0)
                ax.set_yscale("log")
                ax.grid(True, which="major", alpha=0.4)
                ax.set_ylabel(f"validation {quantity} error ({unit})")
                if row == 0:
                    ax.set_title(f"{solver}")
                if row == 1:
                    ax.set_xlabel("iteration")
                ax.legend(fontsize=8)
        fig.suptitle(f"Paper Fig. {3 if cases[0] == '1' else 4} reproduced, cases "
                     f"{cases[0]}-{cases[-1]}: mean error over the validation poses,\n"
                     "median over seeds (line) and 25-75 % band; runs that stopped keep "
                     "their final value", fontsize=11)
        fig.tight_layout()
        fig.savefig(os.path.join(image_dir, filename), dpi=110)
        plt.close(fig)
        written.append(filename)
    return written


def plot_accuracy_vs_time(summary, image_dir):
    cases = list(dict.fromkeys(r["case"] for r in summary))
    solvers = list(dict.fromkeys(r["solver"] for r in summary))
    style = solver_style(solvers)
    ncols = 4
    nrows = math.ceil(len(cases) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(16, 4 * nrows), squeeze=False)
    for i, case in enumerate(cases):
        ax = axes[i // ncols][i % ncols]
        for r in summary:
            if r["case"] != case:
                continue
            color, marker = style[r["solver"]]
            ax.scatter(1e3 * number(r["solve_seconds_median"]),
                       number(r["position_mean_median_mm"]), color=color, marker=marker,
                       s=55, label=r["solver"], edgecolors="black", linewidths=0.4)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="major", alpha=0.4)
        ax.set_title(f"case {case}")
        plain_log_ticks(ax.xaxis)
        plain_log_ticks(ax.yaxis)
        ax.set_xlabel("median time per calibration (ms)")
        ax.set_ylabel("median validation position error (mm)")
    for j in range(len(cases), nrows * ncols):
        axes[j // ncols][j % ncols].axis("off")
    handles = [plt.Line2D([], [], color=style[s][0], marker=style[s][1], ls="",
                          markeredgecolor="black", markersize=8, label=s) for s in solvers]
    fig.legend(handles=handles, loc="lower right", bbox_to_anchor=(0.98, 0.05), fontsize=9,
               title="backend")
    fig.suptitle("Accuracy vs time, one point per backend and case (medians over seeds)")
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "accuracy_vs_time.png"), dpi=100)
    plt.close(fig)
    return ["accuracy_vs_time.png"]


def plot_efficiency(summary, image_dir):
    rows = [r for r in summary if math.isfinite(number(r["efficiency_parameters"]))]
    cases = list(dict.fromkeys(r["case"] for r in rows))
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    style = solver_style(solvers)
    fig, axes = plt.subplots(1, 2, figsize=(15, 5.5), sharey=True)
    width = 0.8 / max(len(solvers), 1)
    for ax, key, title in [(axes[0], "efficiency_parameters", "parameters"),
                           (axes[1], "efficiency_position", "validation position")]:
        for k, solver in enumerate(solvers):
            xs, ys = [], []
            for c, case in enumerate(cases):
                match = [r for r in rows if r["case"] == case and r["solver"] == solver]
                if match:
                    xs.append(c - 0.4 + (k + 0.5) * width)
                    ys.append(number(match[0][key]))
            ax.bar(xs, ys, width=width, color=style[solver][0], label=solver,
                   edgecolor="black", linewidth=0.3)
        ax.axhline(1.0, color="black", lw=1, ls="--")
        ax.set_yscale("log")
        ax.set_xticks(range(len(cases)))
        ax.set_xticklabels([f"case {c}" for c in cases])
        ax.grid(True, axis="y", which="both", alpha=0.3)
        plain_log_ticks(ax.yaxis)
        ax.set_title(f"{title}: Monte Carlo RMS / Cramér-Rao RMS")
    axes[0].set_ylabel("efficiency (1 = at the bound)")
    axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Efficiency against the Cramér-Rao bound σ²(JᵀJ)⁻¹ "
                 "(case 1 is noise-free: no bound)")
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "efficiency_vs_cramer_rao.png"), dpi=100)
    plt.close(fig)
    return ["efficiency_vs_cramer_rao.png"]


def micro_entries(micro):
    """name -> (time in ms, counters); medians when the run had repetitions."""
    entries = {}
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    has_aggregates = any(b.get("run_type") == "aggregate" for b in micro["benchmarks"])
    for b in micro["benchmarks"]:
        if has_aggregates and b.get("aggregate_name") != "median":
            continue
        name = b.get("run_name", b["name"])
        entries[name] = (b["real_time"] * scale[b["time_unit"]], b)
    return entries


def plot_scaling(micro, image_dir):
    entries = micro_entries(micro)
    series = {}
    for name, (ms, _) in entries.items():
        if not name.startswith("BM_Scaling/"):
            continue
        parts = dict(p.split(":", 1) for p in name.split("/") if ":" in p)
        solver = name.split("/")[1]
        series.setdefault((solver, int(parts["threads"])), []).append((int(parts["m"]), ms))
    if not series:
        return []
    fig, ax = plt.subplots(figsize=(7, 5))
    for (solver, threads), points in sorted(series.items()):
        points.sort()
        ax.plot([p[0] for p in points], [p[1] for p in points], "-o",
                label=f"{solver}, {threads} thread{'s' if threads > 1 else ''}")
    # Linear reference through the largest single-thread point (small m takes more iterations).
    m0, t0 = sorted(next(iter(sorted(series.items())))[1])[-1]
    ms = [60, m0]
    ax.plot(ms, [t0 * m / m0 for m in ms], "k:", lw=1, label="linear in m")
    ax.plot([60000], [1000], "r*", ms=14, ls="", label="target: m = 60000 in 1 s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_xlabel("configurations m")
    ax.set_ylabel("full calibration from nominal (ms)")
    ax.set_title("Scaling: calibration time vs number of configurations")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "scaling.png"), dpi=100)
    plt.close(fig)
    return ["scaling.png"]


def write_micro_table(micro, path):
    entries = micro_entries(micro)
    lines = ["| benchmark | time (median) | solver iterations | final cost | param. RMS (mm) |",
             "|---|---|---|---|---|"]
    for name, (ms, b) in entries.items():
        time = (f"{ms * 1e3:.3g} µs" if ms < 1 else f"{ms:.3g} ms" if ms < 1000
                else f"{ms / 1e3:.3g} s")
        name = name.replace("/real_time", "")
        extra = ["–", "–", "–"]
        if "final_cost" in b:
            extra = [f"{b['solver_iterations']:.0f}", f"{b['final_cost']:.7g}",
                     f"{b['param_rms_mm']:.4g}"]
        lines.append(f"| {name} | {time} | " + " | ".join(extra) + " |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    results, images = sys.argv[1], sys.argv[2]
    os.makedirs(images, exist_ok=True)
    written = []
    summary_path = os.path.join(results, "summary.csv")
    if os.path.exists(summary_path):
        summary = read_csv(summary_path)
        written += plot_paper_figures(read_csv(os.path.join(results, "traces.csv")), images)
        written += plot_accuracy_vs_time(summary, images)
        written += plot_efficiency(summary, images)
    micro_path = os.path.join(results, "micro.json")
    if os.path.exists(micro_path):
        with open(micro_path) as f:
            micro = json.load(f)
        written += plot_scaling(micro, images)
        write_micro_table(micro, os.path.join(results, "micro.md"))
    for name in written:
        print(os.path.join(images, name))


if __name__ == "__main__":
    main()
