#!/usr/bin/env python3
"""Z and beta P d^2 of hard disks over a window of a run's log, with a standard error from blocks.

    /usr/bin/python3 scripts/log_window.py RUN/log.csv --phi 0.716 --from 12000 --to 18000

A run's summary measures from its --equilibrate time to its end. A chain continued from its
checkpoint past the time its start is forgotten keeps the earlier window; this measures any later
one from the log instead (`carom run ... --log log.csv --log-every T`: each row's `Z` is the
compressibility factor over the interval since the row before, so rows of equal intervals
average to Z over the window), with the mean of the rows' pressure tensors (pxx, pyy, pxy: in
a solid that a periodic box strains, it tells one state from another; for event chains, whose
rows hold unequal shares of each axis's chains, it is close to the run's own tensor, not equal).
The window's rows are cut into --blocks contiguous blocks (6 by default); the error is the
standard deviation of the block means over sqrt(blocks), as a run's block error is, and says
nothing of slower changes than a block (compare two starts for those).
beta P d^2 = Z 4 phi / pi for equal disks of diameter d. Several logs give one line each and, for
more than one, their mean as scripts/plot_loop.py takes a packing's tasks' (mean_of_runs).

--tau adds the integrated autocorrelation time of the rows' Z over the window, as
scripts/decorrelation.py measures it (Sokal's automatic window; resolved where the window closed
and the rows span 50 times it, else a lower bound, "> "), in time units and, with --cpu-per-unit
S (the CPU seconds a unit of the run costs), in CPU seconds: how long Z remembers itself, which
no block error shows.
"""
import argparse
import csv
import math
import statistics
import sys

from plot_loop import mean_of_runs


def window_rows(path, start, end):
    """The log's interval rows with a Z in (start, end]."""
    with open(path, newline="") as f:
        return [row for row in csv.DictReader(f) if row.get("Z") and start < float(row["time"]) <= end]


def window_z(rows, blocks):
    """(Z over the rows, its block error)."""
    z = [float(row["Z"]) for row in rows]
    size = len(z) // blocks
    means = [statistics.fmean(z[k * size:(k + 1) * size]) for k in range(blocks)]
    return statistics.fmean(z), statistics.stdev(means) / math.sqrt(blocks)


def window_stress(rows):
    """The mean of the rows' pressure tensors in 2D (pxx, pyy, pxy), or None."""
    if not all(row.get(key) for row in rows for key in ("pxx", "pyy", "pxy")):
        return None
    return tuple(statistics.fmean(float(row[key]) for row in rows) for key in ("pxx", "pyy", "pxy"))


def window_tau(rows, cpu_per_unit):
    """The integrated autocorrelation time of the rows' Z, as text: in time units (the rows'
    interval), and in CPU seconds where cpu_per_unit is given."""
    from decorrelation import autocorrelation, describe, integrated_time
    times = [float(row["time"]) for row in rows]
    interval = (times[-1] - times[0]) / (len(times) - 1)
    z = [float(row["Z"]) for row in rows]
    tau, _, resolved, error = integrated_time(autocorrelation(z), len(z))
    units, cpu = describe(tau, resolved, error, interval, cpu_per_unit or 0.0)
    return f"tau of Z {units} units" + (f" ({cpu} CPU s)" if cpu_per_unit else "") + \
        f", {len(z) / tau:.0f} tau spanned"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+", help="run logs (log.csv) with a Z column")
    ap.add_argument("--phi", type=float, required=True, help="the packing fraction, for beta P d^2")
    ap.add_argument("--from", dest="start", type=float, required=True, help="window start (time)")
    ap.add_argument("--to", dest="end", type=float, required=True, help="window end (time)")
    ap.add_argument("--blocks", type=int, default=6, help="blocks for the error (default 6)")
    ap.add_argument("--tau", action="store_true",
                    help="also the integrated autocorrelation time of the rows' Z")
    ap.add_argument("--cpu-per-unit", type=float,
                    help="with --tau: the CPU seconds a time unit of the run costs")
    args = ap.parse_args()
    if args.cpu_per_unit is not None and not (args.tau and args.cpu_per_unit > 0):
        ap.error("--cpu-per-unit takes a positive number of CPU seconds, with --tau")
    if args.blocks < 2:
        ap.error(f"--blocks must be 2 or more (an error needs two block means), got {args.blocks}")
    to_bp = 4.0 * args.phi / math.pi
    values = []
    for path in args.logs:
        rows = window_rows(path, args.start, args.end)
        if len(rows) < 2 * args.blocks:
            sys.exit(f"{path}: {len(rows)} rows in ({args.start}, {args.end}], fewer than two a block")
        z, err = window_z(rows, args.blocks)
        values.append((z * to_bp, err * to_bp))
        line = f"{path}: Z {z:.5f} +- {err:.5f}, beta P d^2 {z * to_bp:.5f} +- {err * to_bp:.5f} ({len(rows)} rows)"
        stress = window_stress(rows)
        if stress:
            line += ", pxx {:.4f} pyy {:.4f} pxy {:.4f}".format(*stress)
        if args.tau:
            line += ", " + window_tau(rows, args.cpu_per_unit)
        print(line)
    if len(values) > 1:
        mean, err = mean_of_runs(values)
        print(f"mean of {len(values)}: beta P d^2 {mean:.5f} +- {err:.5f}")


if __name__ == "__main__":
    main()
