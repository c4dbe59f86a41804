#!/usr/bin/env python3
"""Plots of kincal-solver-suite-benchmark (matplotlib, Agg backend, no other deps).

usage: plot_solver_suite.py RESULTS_DIR IMAGE_DIR

RESULTS_DIR holds suite.csv and (optionally) dimension.csv. Writes solver_suite.png (where each
backend ends on the Moré-Garbow-Hillstrom suite) and derivative_free_vs_n.png (derivative-free
NLopt against the number of parameters) to IMAGE_DIR.
"""

import collections
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def plot_suite(rows, image_dir):
    """One bar per backend (table order): published minimum, published local minimum, other."""
    order, counts = [], collections.OrderedDict()
    for r in rows:
        if r["evaluable"] != "1":
            continue
        label = r["backend"]
        if label not in counts:
            order.append(label)
            counts[label] = collections.Counter()
        counts[label][r["outcome"]] += 1
        counts[label]["broken"] += r["contract_ok"] != "1"
    fig, ax = plt.subplots(figsize=(9, 0.42 * len(order) + 1.4))
    y = list(range(len(order)))[::-1]
    left = [0] * len(order)
    for outcome, color in (("published minimum", "tab:green"),
                           ("published local minimum", "gold"),
                           ("elsewhere", "lightgray")):
        values = [counts[label][outcome] for label in order]
        ax.barh(y, values, left=left, color=color, label=outcome, edgecolor="white")
        left = [a + b for a, b in zip(left, values)]
    for yi, label in zip(y, order):
        solved = counts[label]["published minimum"]
        total = sum(counts[label][k] for k in
                    ("published minimum", "published local minimum", "elsewhere"))
        note = f"{solved}/{total}"
        if counts[label]["broken"]:
            note += f"  ({counts[label]['broken']} broken contracts)"
        ax.text(total + 1, yi, note, va="center", fontsize=8)
    ax.set_yticks(y)
    ax.set_yticklabels(order, fontsize=8)
    ax.set_xlabel("starts of the Moré-Garbow-Hillstrom suite (41 problems x up to 3 starts)")
    ax.set_xlim(0, max(left) * 1.22)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=8,
               title="where the solve ended", title_fontsize=8)
    ax.set_title("Which published minimum each backend reaches (default options)", fontsize=10)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    path = os.path.join(image_dir, "solver_suite.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_dimension(rows, image_dir):
    """Share of the scalable problems solved, and evaluations used, against n."""
    by = collections.defaultdict(lambda: collections.defaultdict(list))
    for r in rows:
        by[r["backend"]][int(r["n"])].append(r)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    cmap = plt.get_cmap("tab10")
    for i, (backend, sizes) in enumerate(sorted(by.items(), key=lambda kv: kv[0] != "lm")):
        ns = sorted(sizes)
        share = [sum(r["solved"] == "1" for r in sizes[n]) / len(sizes[n]) for n in ns]
        evals = []
        for n in ns:
            used = sorted(int(r["residual_evaluations"]) for r in sizes[n] if r["solved"] == "1")
            evals.append(used[len(used) // 2] if used else float("nan"))
        style = dict(color=cmap(i % 10), marker="os^Dv<>p"[i % 8], label=backend,
                     linestyle="--" if backend.startswith("nlopt:LN_") else "-")
        left.plot(ns, share, **style)
        right.plot(ns, evals, **style)
    left.set_xlabel("number of parameters n")
    left.set_ylabel("share of the 8 scalable problems solved")
    left.set_ylim(-0.05, 1.05)
    left.axvline(10, color="gray", linewidth=0.8, linestyle=":")
    right.set_xlabel("number of parameters n")
    right.set_ylabel("evaluations to the minimum (median)")
    right.set_yscale("log")
    right.axvline(10, color="gray", linewidth=0.8, linestyle=":")
    right.legend(fontsize=7, loc="upper left")
    fig.suptitle("Derivative-free NLopt (dashed) against n: budget 20000 evaluations, start x0",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    path = os.path.join(image_dir, "derivative_free_vs_n.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    results, images = sys.argv[1], sys.argv[2]
    os.makedirs(images, exist_ok=True)
    print(plot_suite(read_csv(os.path.join(results, "suite.csv")), images))
    dimension = os.path.join(results, "dimension.csv")
    if os.path.exists(dimension):
        print(plot_dimension(read_csv(dimension), images))


if __name__ == "__main__":
    main()
