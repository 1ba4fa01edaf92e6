#!/usr/bin/env python3
"""Z and beta P d^2 of hard disks over a window of a run's log, with a standard error from blocks.

    /usr/bin/python3 scripts/log_window.py RUN/log.csv --phi 0.716 --from 12000 --to 18000

A run's summary measures from its --equilibrate time to its end. A chain continued from its
checkpoint past the time its start is forgotten keeps the earlier window; this measures any later
one from the log instead (`carom run ... --log log.csv --log-every T`: each row's `Z` is the
compressibility factor over the interval since the row before, so rows of equal intervals
average to Z over the window), with the window's pressure tensor (pxx, pyy, pxy: in a solid
that a periodic box strains, it tells one state from another): the mean of the rows' for
dynamics, and for event chains, whose rows hold unequal shares of each axis's moves, the run's
own from the running sums the rows end at (Kxx, ..., Wxx, ...: beta P_kk = N / V (1 + dW_kk /
dK_kk) over the window, N / V = 4 phi / pi for disks of diameter 1).
The window's rows are cut into --blocks contiguous blocks (6 by default); the error is the
standard deviation of the block means over sqrt(blocks), as a run's block error is, and says
nothing of slower changes than a block (compare two starts for those).
beta P d^2 = Z 4 phi / pi for equal disks of diameter d. Several logs give one line each and, for
more than one, their mean as scripts/plot_loop.py takes a packing's tasks' (mean_of_runs).
"""
import argparse
import csv
import math
import statistics
import sys

from plot_loop import mean_of_runs


def window_rows(path, start, end):
    """The log's interval rows with a Z in (start, end], and the last row at or before start (the
    running sums the window's begin from; None if there is none)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    before = [row for row in rows if float(row["time"]) <= start]
    inside = [row for row in rows if row.get("Z") and start < float(row["time"]) <= end]
    return inside, (before[-1] if before else None)


def window_z(rows, blocks):
    """(Z over the rows, its block error)."""
    z = [float(row["Z"]) for row in rows]
    size = len(z) // blocks
    means = [statistics.fmean(z[k * size:(k + 1) * size]) for k in range(blocks)]
    return statistics.fmean(z), statistics.stdev(means) / math.sqrt(blocks)


def window_stress(rows, origin, density):
    """The window's pressure tensor in 2D (pxx, pyy, pxy), or None: event chains' from the
    differences of their running sums (moves K, lifts W) between `origin` and the last row, as
    their summary's (the diagonal over each axis's moves, xy over both axes'); dynamics' the mean
    of the rows' tensors."""
    if "Kxx" in rows[0]:
        if origin is None:
            return None
        d = {key: float(rows[-1][key]) - float(origin[key])
             for key in ("Kxx", "Kyy", "Wxx", "Wyy", "Wxy")}
        if not (d["Kxx"] > 0 and d["Kyy"] > 0):
            return None
        return (density * (1 + d["Wxx"] / d["Kxx"]), density * (1 + d["Wyy"] / d["Kyy"]),
                density * 2 * d["Wxy"] / (d["Kxx"] + d["Kyy"]))
    if not all(row.get(key) for row in rows for key in ("pxx", "pyy", "pxy")):
        return None
    return tuple(statistics.fmean(float(row[key]) for row in rows) for key in ("pxx", "pyy", "pxy"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+", help="run logs (log.csv) with a Z column")
    ap.add_argument("--phi", type=float, required=True, help="the packing fraction, for beta P d^2")
    ap.add_argument("--from", dest="start", type=float, required=True, help="window start (time)")
    ap.add_argument("--to", dest="end", type=float, required=True, help="window end (time)")
    ap.add_argument("--blocks", type=int, default=6, help="blocks for the error (default 6)")
    args = ap.parse_args()
    if args.blocks < 2:
        ap.error(f"--blocks must be 2 or more (an error needs two block means), got {args.blocks}")
    to_bp = 4.0 * args.phi / math.pi
    values = []
    for path in args.logs:
        rows, origin = window_rows(path, args.start, args.end)
        if len(rows) < 2 * args.blocks:
            sys.exit(f"{path}: {len(rows)} rows in ({args.start}, {args.end}], fewer than two a block")
        z, err = window_z(rows, args.blocks)
        values.append((z * to_bp, err * to_bp))
        line = f"{path}: Z {z:.5f} +- {err:.5f}, beta P d^2 {z * to_bp:.5f} +- {err * to_bp:.5f} ({len(rows)} rows)"
        stress = window_stress(rows, origin, to_bp)
        if stress:
            line += ", pxx {:.4f} pyy {:.4f} pxy {:.4f}".format(*stress)
        print(line)
    if len(values) > 1:
        mean, err = mean_of_runs(values)
        print(f"mean of {len(values)}: beta P d^2 {mean:.5f} +- {err:.5f}")


if __name__ == "__main__":
    main()
