#!/usr/bin/env python3
"""How long a run's series remembers itself: the integrated autocorrelation time of Z from a run's
log, or of the global |psi6| from `carom analyze --only psi6`, over a window.

    /usr/bin/python3 scripts/series_tau.py RUN/log.csv --from 7500 --to 18000 --cpu-per-unit 0.66
    build/carom analyze frames.gsd --only psi6 -o psi6.json
    /usr/bin/python3 scripts/series_tau.py psi6.json --from 13520 --cpu-per-unit 0.66

A log (`carom run --log log.csv --log-every T`) gives each row's Z over the interval that ends at
its time, taken in (from, to]; an analysis JSON gives |psi6| of each frame (`psi6.global`, at
`psi6.t`), taken in [from, to] (as `carom analyze --equilibrate` takes frames). Either series is
measured as scripts/decorrelation.py measures its own: the normalised autocorrelation function
and tau = 1 + 2 sum_k rho(k) in rows, with Sokal's automatic window (the smallest M with
M >= 5 tau(M)) and his error, resolved where the window closed and the series spans 50 tau or
more, else a lower bound ("> "); tau in time units (rows evenly spaced) and, with --cpu-per-unit S
(the CPU seconds a time unit of the run costs), in CPU seconds. The runs of a resumed chain give
one series: a window must hold rows of one spacing.
"""
import argparse
import csv
import json
import sys

from decorrelation import autocorrelation, describe, integrated_time


def log_series(path):
    """(times, Z) of a run log's interval rows: each over the interval that ends at its time."""
    with open(path, newline="") as f:
        rows = [row for row in csv.DictReader(f) if row.get("Z")]
    return [float(r["time"]) for r in rows], [float(r["Z"]) for r in rows]


def psi6_series(path):
    """(times, global |psi6|) of carom analyze's JSON."""
    with open(path) as f:
        psi6 = json.load(f).get("psi6")
    if not psi6:
        sys.exit(f"{path}: no psi6 in this analysis (disks analysed with psi6: --only psi6)")
    return psi6["t"], psi6["global"]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("series", help="a run's log (.csv: Z) or carom analyze's JSON (.json: psi6)")
    ap.add_argument("--from", dest="start", type=float, default=-float("inf"),
                    help="window start (time; default: the first row)")
    ap.add_argument("--to", dest="end", type=float, default=float("inf"),
                    help="window end (time; default: the last row)")
    ap.add_argument("--cpu-per-unit", type=float,
                    help="the CPU seconds a time unit of the run costs, for tau in CPU seconds")
    args = ap.parse_args()
    if args.cpu_per_unit is not None and not args.cpu_per_unit > 0:
        ap.error(f"--cpu-per-unit must be a positive number of CPU seconds, "
                 f"not {args.cpu_per_unit}")
    frames = args.series.endswith(".json")
    what, (times, values) = (("|psi6|", psi6_series(args.series)) if frames
                             else ("Z", log_series(args.series)))
    inside = ((lambda t: args.start <= t <= args.end) if frames
              else (lambda t: args.start < t <= args.end))
    kept = [(t, v) for t, v in zip(times, values) if inside(t)]
    if len(kept) < 3:
        sys.exit(f"{args.series}: {len(kept)} rows in the window, fewer than 3")
    times, values = zip(*kept)
    spacings = [b - a for a, b in zip(times, times[1:])]
    interval = (times[-1] - times[0]) / (len(times) - 1)
    if max(spacings) - min(spacings) > 1e-6 * interval:
        sys.exit(f"{args.series}: rows {min(spacings):g} to {max(spacings):g} apart in the "
                 "window; tau needs evenly spaced rows")
    if max(values) == min(values):
        sys.exit(f"{args.series}: {what} is {values[0]:g} in every row: no fluctuation to "
                 "correlate")
    tau, _, resolved, error = integrated_time(autocorrelation(values), len(values))
    units, cpu = describe(tau, resolved, error, interval, args.cpu_per_unit or 0.0)
    span = (f"[{times[0]:g}, {times[-1]:g}]" if frames
            else f"({times[0] - interval:g}, {times[-1]:g}]")
    print(f"{args.series}: tau of {what} {units} units" +
          (f" ({cpu} CPU s)" if args.cpu_per_unit else "") +
          f" over {span}, {len(values)} rows {interval:g} apart, "
          f"{len(values) / tau:.0f} tau spanned, mean {sum(values) / len(values):.5g}")


if __name__ == "__main__":
    main()
