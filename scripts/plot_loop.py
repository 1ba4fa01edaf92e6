#!/usr/bin/env python3
"""The hard-disk pressure loop: a sweep's beta P d^2 against packing, beside the published one.

    carom sweep examples/hard_disk_loop.toml -o hard_disk_loop          # hours: see the plan
    /usr/bin/python3 scripts/plot_loop.py hard_disk_loop/results.csv    # -> docs/images/hard_disk_loop.svg

Reads a sweep's results.csv (or the sweep's folder): one row a task with `phi` (a swept key, or
the `packing_fraction` column), `status`, `Z` and `Z_error`. beta P d^2 = Z N d^2 / V = Z 4 phi / pi
for equal disks of diameter d (Z = P V / (N kT), so neither kT nor the unit of length enters).
Tasks of one packing (several seeds) are averaged; the error is the larger of their block-average
errors combined and the standard error of their scatter (one task: its run's block error). Where
the runs of the packings measured more than once scatter beyond their errors (chi2 over its
degrees of freedom above 1), every run's error is first multiplied by sqrt(chi2 / dof), the
scale factor the Particle Data Group applies to measurements that disagree: a run's blocks can be
shorter than its slowest fluctuation. Tasks not done are left out and counted.

Drawn beside it from docs/data/historic_disks/ (HistoricDisks, GPL-3.0): E. P. Bernard and
W. Krauth, Phys. Rev. Lett. 107, 155704 (2011) (event-chain Monte Carlo) and M. Engel et al.,
Phys. Rev. E 87, 042134 (2013) (massively parallel Monte Carlo and event-driven MD), at the N
of the sweep (--n, default 256^2 = 65536). Also prints a Markdown table of carom's points next
to theirs at the same packing, the difference in combined standard errors.
"""
import argparse
import csv
import math
import os
import sys

import historic_disks

# (file, sampling method as the file spells it, label, marker)
REFERENCES = [
    ("Bernard_2011.csv", "straight ECMC", "Bernard & Krauth 2011 (ECMC)", "s"),
    ("Engel_2013.csv", "MPMC", "Engel et al. 2013 (MPMC)", "^"),
    ("Engel_2013.csv", "EDMD", "Engel et al. 2013 (EDMD)", "v"),
]


def read_results(path, scale_from=None):
    """{phi: (beta P d^2, error, runs, windows)} over the done runs, and the count not done.

    Reads a sweep's results.csv (or its folder), one row a task (`phi` or `packing_fraction`,
    `status`, `Z`, `Z_error`), or a table of chains (docs/data/hard_disk_loop_runs.csv: `phi`,
    `from`, `to`, `beta_p`, `error`, with `#` comment lines), one row a chain measured over the
    window [from, to]. The errors are scaled by error_scale over the packings from
    scale_from[0] to scale_from[1] (all when None)."""
    if os.path.isdir(path):
        path = os.path.join(path, "results.csv")
    by_phi, windows, not_done = {}, {}, 0
    with open(path, newline="") as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            if "beta_p" in row:
                phi = round(float(row["phi"]), 9)
                by_phi.setdefault(phi, []).append((float(row["beta_p"]), float(row["error"])))
                windows.setdefault(phi, set()).add(f"{row['from']}-{row['to']}")
                continue
            if row.get("status", "done") != "done" or not row.get("Z"):
                not_done += 1
                continue
            phi = float(row.get("phi") or row["packing_fraction"])
            z = float(row["Z"])
            z_err = float(row["Z_error"]) if row.get("Z_error") else float("nan")
            to_bp = 4.0 * phi / math.pi
            by_phi.setdefault(round(phi, 9), []).append((z * to_bp, z_err * to_bp))
    lo, hi = scale_from or (-math.inf, math.inf)
    scale = error_scale(vals for phi, vals in by_phi.items() if lo <= phi <= hi)
    points = {}
    for phi, vals in sorted(by_phi.items()):
        window = ", ".join(sorted(windows.get(phi, ()), key=lambda w: int(w.split("-")[0])))
        scaled = [(v, e * scale[0]) for v, e in vals]
        points[phi] = (*mean_of_runs(scaled), len(vals), window)
    return points, not_done, scale


def error_scale(groups):
    """(S, chi2, degrees of freedom, groups): how much runs of one packing scatter beyond their
    errors, S = sqrt(chi2 / dof) of each group's runs about their weighted mean, pooled over the
    groups of two runs or more (the Particle Data Group's scale factor). Runs whose errors come
    from blocks shorter than the slowest fluctuation scatter more than those errors say; every
    run's error is multiplied by S where it exceeds 1 (1 without two runs of a packing)."""
    chi2, dof, used = 0.0, 0, 0
    for vals in groups:
        if len(vals) < 2 or any(not e > 0 for _, e in vals):
            continue
        weights = [1.0 / (e * e) for _, e in vals]
        mean = sum(w * v for w, (v, _) in zip(weights, vals)) / sum(weights)
        chi2 += sum(((v - mean) / e) ** 2 for v, e in vals)
        dof += len(vals) - 1
        used += 1
    return (max(1.0, math.sqrt(chi2 / dof)) if dof else 1.0), chi2, dof, used


def mean_of_runs(values):
    """(mean, error) of runs' (value, error) pairs: the error is the larger of the runs' errors
    combined and the scatter of their means, since two runs can agree by chance far better than
    either is known (one run: its own error)."""
    k = len(values)
    mean = sum(v for v, _ in values) / k
    err = math.sqrt(sum(e * e for _, e in values)) / k
    if k > 1:
        err = max(err, math.sqrt(sum((v - mean) ** 2 for v, _ in values) / (k - 1) / k))
    return mean, err


def reference(file, sampling, n, data):
    try:
        group = historic_disks.find_group(os.path.join(data, file), n, "(1 : 1)", sampling)
    except LookupError:
        return None
    return {round(x, 9): (y, e) for x, y, e in group["points"]}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="the sweep's results.csv, or its folder")
    parser.add_argument("-o", "--output",
                        default=os.path.join(os.path.dirname(here), "docs", "images",
                                             "hard_disk_loop.svg"),
                        help="the figure (.svg or .png; default docs/images/hard_disk_loop.svg)")
    parser.add_argument("--n", type=int, default=65536,
                        help="the sweep's N, whose published data are drawn (default 65536)")
    parser.add_argument("--label", help="the legend of carom's points (default: carom (ECMC), N)")
    parser.add_argument("--data", default=historic_disks.DATA, help="the published data folder")
    parser.add_argument("--scale-from", nargs=2, type=float, metavar=("LO", "HI"),
                        help="take the errors' scale factor from the packings LO to HI only "
                             "(default: every packing measured more than once)")
    args = parser.parse_args()

    points, not_done, scale = read_results(args.results, args.scale_from)
    if not points:
        sys.exit(f"{args.results}: no task done yet ({not_done} not done)")
    refs = [(label, marker, reference(file, sampling, args.n, args.data))
            for file, sampling, label, marker in REFERENCES]
    refs = [r for r in refs if r[2]]

    import matplotlib
    matplotlib.use("Agg")
    matplotlib.rcParams["svg.hashsalt"] = "carom"
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for label, marker, data in refs:
        xs = sorted(data)
        ax.errorbar(xs, [data[x][0] for x in xs], yerr=[data[x][1] for x in xs], marker=marker,
                    ms=4, lw=0.8, capsize=2, fillstyle="none", label=f"{label}, N = {args.n}")
    xs = sorted(points)
    ax.errorbar(xs, [points[x][0] for x in xs], yerr=[points[x][1] for x in xs], marker="o",
                ms=5, lw=1.2, capsize=3, color="black",
                label=args.label or f"carom (ECMC), N = {args.n}")
    ax.set_xlabel("packing fraction $\\eta$")
    ax.set_ylabel("$\\beta P d^2$")
    ax.set_title("Hard disks: the pressure loop of the liquid-hexatic transition")
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output, metadata={"Date": None} if args.output.endswith(".svg") else None)

    names = [label for label, _, _ in refs]
    windows = any(points[x][3] for x in xs)
    print("| packing | carom beta P d^2 | " + ("chains | window |" if windows else "tasks |") + " "
          + " | ".join(names) + " |")
    print("|---|---|---|" + ("---|" if windows else "") + "---|" * len(names))
    within = 0
    for x in xs:
        m, e, k, window = points[x]
        cells = []
        for i, (_, _, data) in enumerate(refs):
            if x not in data:
                cells.append("-")
                continue
            y, ye = data[x]
            dev = difference(m, e, y, ye)
            within += i == 0 and abs(dev) <= 2.0
            cells.append(f"{y:.5f} +- {ye:.5f} ({dev:+.1f})")
        runs = f"{k} | {window}" if windows else f"{k}"
        print(f"| {x:.3f} | {m:.5f} +- {e:.5f} | {runs} | " + " | ".join(cells) + " |")
    factor, chi2, dof, groups = scale
    print(f"\n{len(xs)} packings done, {not_done} tasks not done; {within} of {len(xs)} within two "
          f"combined errors of {names[0]}; figure: {args.output}")
    if factor > 1:
        among = (f" from {args.scale_from[0]:g} to {args.scale_from[1]:g}" if args.scale_from
                 else "")
        packings = "packing" if groups == 1 else "packings"
        print(f"Every run's error multiplied by {factor:.2f}: the runs of the {groups} {packings}"
              f"{among} measured more than once scatter by chi2 = {chi2:.1f} over {dof} degrees of "
              f"freedom about their means, sqrt(chi2 / dof) = {math.sqrt(chi2 / dof):.2f} times "
              f"what their errors say")


def difference(value, error, reference_value, reference_error):
    """value - reference in combined standard errors (nan when neither has an error)."""
    combined = math.hypot(error, reference_error)
    return (value - reference_value) / combined if combined > 0 else float("nan")


if __name__ == "__main__":
    main()
