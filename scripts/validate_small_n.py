#!/usr/bin/env python3
"""Hard disks at small N against Li et al. 2022: carom's beta P d^2 next to the published one.

Regenerates the table "Hard disks at small N against Li et al. 2022" in docs/validation.md:
    /usr/bin/python3 scripts/validate_small_n.py [--sampler md|ecmc] [--quick] [--carom build/carom]

Reference: B. Li, Y. Nishikawa, P. Hoellmer, L. Carillo, A. C. Maggs, W. Krauth, "Hard-disk
pressure computations - a historic perspective", J. Chem. Phys. 157, 234111 (2022), event-chain
Monte Carlo; their data file DigitizedData/ThisWork.csv of github.com/jellyfysh/HistoricDisks,
copied unmodified to docs/data/historic_disks/ (beta P (2 sigma)^2 with sigma the radius, that is
beta P d^2 with d the diameter; errors are one standard error).

State points: N = 72 in a square periodic box at packing 0.65, 0.67, 0.69, 0.70, 0.72, and
N = 870 in a periodic box of sides 29 : 30 sqrt(3)/2 (a 29 x 30 triangular lattice fits it;
`carom init --aspect 29/(15 sqrt(3))`) at 0.67 to 0.71.

Each state point: --replicas independent runs, half of them from `carom init`'s triangular
lattice (--seed s; for event chains melted first by one unit of dynamics, since chains can push
the rows of a perfect lattice in a small box into a ring of disks in contact that no chain along
the row moves) and half from a fluid (`carom init --random` at packing 0.4, --seed s, grown to
the packing by `carom compress --unit-diameter`), so that a start that has not been forgotten
shows as a difference between the two halves. Each run is `carom run START T --equilibrate TE
--log ... --summary ...` (with --sampler and --chain-length passed through when given, and for
event chains the run's --seed, which draws the chains' particles); T and TE are chosen from a
short trial run so that the run has about --events events (collisions, or lifts and chain ends)
measured after --equilibrate-events. beta P d^2 = Z N d^2 / (Lx Ly): kT = 1 and Z = P V / (N kT) as carom
reports it. A run's error is the block-average error of its log (Flyvbjerg-Petersen); the state
point's value is the mean over the runs, its error the larger of the runs' block errors combined
and the scatter of the runs' means (over sqrt(runs)). The table compares it with the published
value in combined standard errors; the exit status is 1 when a point lies more than --tolerance
combined errors away (2 by default: with ten points, that happens by chance once in about three
tables, so look at the chi^2 line and run longer before concluding).
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time

from carom_binary import carom_binary

import historic_disks

SQRT3 = math.sqrt(3.0)

# (N, aspect ratio as ThisWork.csv spells it, box label, Lx / Ly, packing fractions)
SYSTEMS = [
    (72, "(1 : 1)", "square", 1.0, [0.65, 0.67, 0.69, 0.70, 0.72]),
    (870, r"(29 : 30 \sqrt{3} / 2)", "29 : 30 sqrt(3)/2", 29.0 / (15.0 * SQRT3),
     [0.67, 0.68, 0.69, 0.70, 0.71]),
]


def published(path, n, aspect_text, eta):
    group = historic_disks.find_group(path, n, aspect_text, sampling="ECMC")
    for x, y, err in group["points"]:
        if abs(x - eta) < 1e-9:
            return y, err
    raise LookupError(f"{path}: no N = {n} {aspect_text} point at packing {eta}")


def run(cmd):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {done.returncode}: {done.stderr.strip()[:400]}")
    return done.stdout


def read_json(path):
    with open(path) as f:
        return json.load(f)


def last_log_row(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows[-1]


def sampler_options(args, seed):
    opts = []
    if args.sampler != "md":
        # The run's seed draws the chains' particles: without it two runs from one lattice
        # (whose seeds differ only in velocities, which chains ignore) would be the same run.
        opts += ["--sampler", args.sampler, "--seed", str(seed)]
    if args.chain_length is not None:
        opts += ["--chain-length", repr(args.chain_length)]
    return opts


def make_start(carom, n, aspect, eta, seed, kind, path, sampler):
    common = ["--n", str(n), "--aspect", repr(aspect), "--boundary", "periodic",
              "--seed", str(seed)]
    if kind == "lattice" and sampler == "ecmc":
        lattice = path + ".lattice.txt"
        run([carom, "init", "--phi", repr(eta), "--lattice", *common, "-o", lattice])
        run([carom, "run", lattice, "1", "--final", path, "-q", "-o", os.devnull])
    elif kind == "lattice":
        run([carom, "init", "--phi", repr(eta), "--lattice", *common, "-o", path])
    else:
        fluid = path + ".fluid.txt"
        run([carom, "init", "--phi", "0.4", "--random", *common, "-o", fluid])
        run([carom, "compress", fluid, "--phi", repr(eta), "--unit-diameter", "-q", "-o", path])


def diameter_of(start):
    """2 R from line 2 of a classic start file (after its comment lines)."""
    with open(start) as f:
        lines = [ln for ln in f if ln.strip() and not ln.startswith("#")]
    return 2.0 * float(lines[1].split()[0])


def one_run(carom, args, n, aspect, eta, seed, kind, folder):
    tag = f"n{n}-eta{eta:.3f}-{kind}-s{seed}"
    start = os.path.join(folder, f"start-{tag}.txt")
    make_start(carom, n, aspect, eta, seed, kind, start, args.sampler)
    d = diameter_of(start)
    extra = sampler_options(args, seed)
    # A trial run gives the events per unit of run time, from which T and TE follow.
    trial = os.path.join(folder, f"trial-{tag}.json")
    run([carom, "run", start, repr(args.trial_time), *extra, "--summary", trial, "-q",
         "-o", os.devnull])
    rate = read_json(trial)["events"] / args.trial_time
    t_eq = args.equilibrate_events / rate
    t_end = t_eq + args.events / rate
    summary = os.path.join(folder, f"summary-{tag}.json")
    log = os.path.join(folder, f"log-{tag}.csv")
    began = time.time()
    run([carom, "run", start, repr(t_end), "--equilibrate", repr(t_eq), *extra,
         "--log", log, "--log-every", repr((t_end - t_eq) / args.log_rows),
         "--summary", summary, "-q", "-o", os.devnull])
    seconds = time.time() - began
    s = read_json(summary)
    lx, ly = s["box"]
    if s["n"] != n or abs(lx / ly - aspect) > 1e-9 or abs(s["packing_fraction"] - eta) > 1e-9:
        raise RuntimeError(f"{tag}: unexpected system n={s['n']} box={s['box']} "
                           f"eta={s['packing_fraction']}")
    if s["boundary"] != "periodic":
        raise RuntimeError(f"{tag}: not a periodic run")
    to_bp = n * d * d / (lx * ly)
    row = last_log_row(log)
    z, z_err = s["compressibility_factor"], float(row["Z_error"])
    drift = s.get("compressibility_factor_drift") or {}
    return {"seed": seed, "kind": kind, "value": z * to_bp, "error": z_err * to_bp,
            "events": s.get("window_events", s["events"]), "seconds": seconds,
            "drift_sigmas": drift.get("sigmas"),
            # Event chains: Z along x and y apart (a strained solid's differ).
            "directional": s.get("directional_compressibility_factor")}


def combine(runs):
    k = len(runs)
    values = [r["value"] for r in runs]
    m = sum(values) / k
    blocks = math.sqrt(sum(r["error"] ** 2 for r in runs)) / k
    scatter = math.sqrt(sum((v - m) ** 2 for v in values) / (k - 1) / k) if k > 1 else 0.0
    return m, max(blocks, scatter), blocks, scatter


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom",
                        help="carom binary (relative paths are tried from the current directory, "
                             "then from the repository root)")
    parser.add_argument("--sampler", default="md", choices=["md", "ecmc"],
                        help="md: event-driven molecular dynamics (carom run's default); "
                             "ecmc: passed on as carom run --sampler ecmc")
    parser.add_argument("--chain-length", type=float,
                        help="passed on as carom run --chain-length (ecmc)")
    parser.add_argument("--quick", action="store_true",
                        help="a smoke run of a few seconds (errors far above the published ones)")
    parser.add_argument("--replicas", type=int, help="runs per state point, half from a lattice "
                                                     "and half from a fluid (default 4)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first run")
    parser.add_argument("--events", type=float,
                        help="events measured per run (default 3e7 md, 1e8 ecmc, whose events "
                             "cost a third; quick 2e5)")
    parser.add_argument("--equilibrate-events", type=float,
                        help="events before measuring, per run (default 1e7 md, 2e7 ecmc; "
                             "quick 5e4)")
    parser.add_argument("--trial-time", type=float, default=1.0,
                        help="length of the trial run that gives the events per unit time")
    parser.add_argument("--log-rows", type=int, default=2000,
                        help="log rows over the measurement (the block analysis' series)")
    parser.add_argument("--n", type=int, action="append", choices=[s[0] for s in SYSTEMS],
                        help="only this N (repeatable)")
    parser.add_argument("--packing", type=float, action="append",
                        help="only this packing fraction (repeatable)")
    parser.add_argument("--jobs", type=int, default=2, help="carom processes at once")
    parser.add_argument("--tolerance", type=float, default=2.0,
                        help="exit 1 when a point lies more than this many combined errors away")
    parser.add_argument("--csv", help="also write the rows to this csv file")
    parser.add_argument("--data", default=os.path.join(historic_disks.DATA, "ThisWork.csv"),
                        help="the published data file")
    args = parser.parse_args()

    carom = carom_binary(args.carom)
    replicas = args.replicas or (2 if args.quick else 4)
    ecmc = args.sampler == "ecmc"
    args.events = args.events or (2e5 if args.quick else 1e8 if ecmc else 3e7)
    args.equilibrate_events = args.equilibrate_events or (5e4 if args.quick else
                                                          2e7 if ecmc else 1e7)
    if replicas < 2:
        sys.exit("--replicas must be at least 2")

    points = []
    for n, aspect_text, label, aspect, etas in SYSTEMS:
        if args.n and n not in args.n:
            continue
        for eta in etas:
            if args.packing and not any(abs(eta - p) < 1e-9 for p in args.packing):
                continue
            points.append((n, aspect_text, label, aspect, eta,
                           *published(args.data, n, aspect_text, eta)))

    if not points:
        sys.exit("no state point left by --n and --packing")
    started = time.time()
    column = "EDMD" if args.sampler == "md" else "ECMC"
    print(f"| N | box Lx : Ly | packing | published beta P d^2 | carom ({column}) beta P d^2 "
          f"| difference / combined error | events per disk |")
    print("|---|---|---|---|---|---|---|", flush=True)
    notes, rows, worst, chi2 = [], [], 0.0, 0.0
    with tempfile.TemporaryDirectory(prefix="carom-small-n-") as folder, \
            concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [[pool.submit(one_run, carom, args, p[0], p[3], p[4], args.seed + r,
                                "lattice" if r % 2 == 0 else "fluid", folder)
                    for r in range(replicas)] for p in points]
        for p, fs in zip(points, futures):
            n, _, label, _, eta, ref, ref_err = p
            runs = [f.result() for f in fs]
            m, err, blocks, scatter = combine(runs)
            combined = math.hypot(err, ref_err)
            dev = (m - ref) / combined
            worst, chi2 = max(worst, abs(dev)), chi2 + dev * dev
            events = sum(r["events"] for r in runs)
            print(f"| {n} | {label} | {eta:.2f} | {ref:.6f} +- {ref_err:.6f} | {m:.4f} +- "
                  f"{err:.4f} | {dev:+.1f} | {events / n:.3g} |", flush=True)
            by_kind = {}
            for kind in ("lattice", "fluid"):
                of_kind = [r for r in runs if r["kind"] == kind]
                if of_kind:
                    by_kind[kind] = combine(of_kind) if len(of_kind) > 1 else \
                        (of_kind[0]["value"], of_kind[0]["error"], 0, 0)
            notes.append(
                f"N={n} eta={eta:.2f}: runs " +
                ", ".join(f"{r['kind'][0]}{r['seed']} {r['value']:.4f}+-{r['error']:.4f}"
                          f" (drift {r['drift_sigmas'] if r['drift_sigmas'] is None else round(r['drift_sigmas'], 1)} sd"
                          + ("; Z along x, y " + " ".join(f"{z:.2f}" for z in r["directional"])
                             if r.get("directional") else "") + ")"
                          for r in runs) +
                f"; error from blocks {blocks:.4f}, from the scatter {scatter:.4f}; " +
                "; ".join(f"{k} starts {v[0]:.4f} +- {v[1]:.4f}" for k, v in by_kind.items()) +
                f"; {sum(r['seconds'] for r in runs):.0f} s of runs")
            rows.append({"n": n, "box": label, "packing": eta, "published": ref,
                         "published_error": ref_err, "sampler": args.sampler, "carom": m,
                         "carom_error": err, "error_blocks": blocks, "error_scatter": scatter,
                         "deviation": dev, "events": events,
                         **{f"{k}_mean": v[0] for k, v in by_kind.items()},
                         **{f"{k}_error": v[1] for k, v in by_kind.items()}})
    print()
    for line in notes:
        print(f"- {line}")
    k = len(points)
    print(f"- chi^2 = {chi2:.1f} for {k} points; largest |difference| {worst:.1f} combined errors")
    print(f"- wall time {time.time() - started:.0f} s with {args.jobs} carom processes at once "
          f"(sampler {args.sampler}, {replicas} runs a point, {args.events:.3g} events measured "
          f"after {args.equilibrate_events:.3g} a run)")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=sorted({key for r in rows for key in r},
                                                    key=lambda key: list(rows[0]).index(key)
                                                    if key in rows[0] else 99))
            w.writeheader()
            w.writerows(rows)
    return 1 if worst > args.tolerance else 0


if __name__ == "__main__":
    sys.exit(main())
