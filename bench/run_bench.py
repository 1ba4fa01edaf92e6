#!/usr/bin/env python3
"""carom's benchmark: collisions per second, instructions per collision and bytes per particle.

Usage: python3 bench/run_bench.py [--carom build/carom] [--name NAME] [--quick] [--no-callgrind]
                                  [--versus OLD/carom]
Runs the real command line on `carom init` systems (elastic rule, periodic box, monodisperse,
kT = 1, seed 1), disks at packing fractions 0.3, 0.5 and 0.7 (N = 10^3..10^6) and spheres
(N = 10^4..10^6) at 0.3 and 0.45: each configuration in its own process, whose peak resident
memory is read from the kernel (wait4). Collisions per second come from the run's own clock
(simulation only, not reading or writing files). Instructions per collision are counted, not
timed (this machine has no hardware counters): callgrind runs the same start twice, to two
lengths, and the difference of the instruction counts over the difference of the collisions
leaves out reading, setting up and writing (N = 10^4). The classic assignment's algorithm (--engine reference:
every pair predicted again after every event) is timed at N = 2000, for the speedup. Each row is
compared with bench/results/baseline.json (an earlier carom on the same kind of machine), or,
with --versus, with another carom binary run side by side: each row alternately by both, the
better of two runs each, so that the ratio holds on a machine whose speed drifts by the hour
(instructions per collision are then counted for both too). Prints a Markdown table and writes
it as json to bench/results/NAME.json (not tracked by git).
"""
import argparse
import datetime
import shutil
import json
import math
import os
import platform
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def henderson(eta):
    return (1 + eta**2 / 8) / (1 - eta) ** 2 - 0.043 * eta**4 / (1 - eta) ** 3


def kolafa_labik_malijevsky(eta):
    return (1 + eta + eta**2 - 2 / 3 * eta**3 * (1 + eta)) / (1 - eta) ** 3


def collision_rate(eta, dim):
    # Per particle per unit time at kT = 1, sigma = 1: omega = 2 D (Z - 1) / sqrt(pi).
    z = henderson(eta) if dim == 2 else kolafa_labik_malijevsky(eta)
    return 2 * dim * (z - 1) / math.sqrt(math.pi)


def run(command):
    """Runs a command; returns its peak resident memory in bytes."""
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    if status != 0:
        sys.exit(f"failed: {' '.join(command)}")
    return usage.ru_maxrss * 1024


def measure(carom, folder, n, eta, collisions, engine="fast", dim=2):
    start = os.path.join(folder, f"start-{dim}d-{n}-{eta}.txt")
    summary = os.path.join(folder, "summary.json")
    if not os.path.exists(start):
        run([carom, "init", "--dim", str(dim), "--n", str(n), "--phi", str(eta), "--boundary",
             "periodic", "--seed", "1", "-o", start])
    end_time = collisions / (n * collision_rate(eta, dim) / 2)
    peak = run([carom, "run", start, f"{end_time:.6g}", "--rule", "elastic", "--boundary",
                "periodic", "--engine", engine, "--format", "csv", "-o", os.devnull,
                "--summary", summary])
    with open(summary) as f:
        s = json.load(f)
    return {"dimension": dim, "n": n, "packing_fraction": eta, "engine": engine,
            "collisions": s["pair_collisions"], "events": s["events"], "seconds": s["wall_seconds"],
            "collisions_per_second": s["pair_collisions"] / s["wall_seconds"],
            "peak_rss_bytes": peak, "bytes_per_particle": peak / n}


def instructions_per_collision(carom, folder, n, eta, dim=2):
    """Instructions per collision by callgrind: (I(long) - I(short)) / (C(long) - C(short))."""
    start = os.path.join(folder, f"start-{dim}d-{n}-{eta}.txt")
    counted = []
    for collisions in (20 * n, 60 * n):
        end_time = collisions / (n * collision_rate(eta, dim) / 2)
        out = os.path.join(folder, "callgrind.out")
        summary = os.path.join(folder, "summary.json")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", carom, "run",
                        start, f"{end_time:.6g}", "--rule", "elastic", "--boundary", "periodic",
                        "--format", "csv", "-o", os.devnull, "--summary", summary, "--quiet"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(out) as f:
            total = next(int(line.split()[1]) for line in f if line.startswith("totals:"))
        with open(summary) as f:
            counted.append((total, json.load(f)["pair_collisions"]))
    (i0, c0), (i1, c1) = counted
    return (i1 - i0) / (c1 - c0)


def shown(value, form):
    """A table cell: empty for a value not measured."""
    return "" if value is None else format(value, form)


def baseline_rates():
    """Collisions per second of bench/results/baseline.json, by (dimension, N, packing)."""
    path = os.path.join(HERE, "results", "baseline.json")
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        runs = json.load(f)["runs"]
    return {(r.get("dimension", 2), r["n"], r["packing_fraction"]): r["collisions_per_second"]
            for r in runs}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--name", default="latest")
    parser.add_argument("--quick", action="store_true", help="N up to 10^5 only")
    parser.add_argument("--no-callgrind", action="store_true",
                        help="skip counting instructions (valgrind is slow)")
    parser.add_argument("--versus", metavar="OLD_CAROM",
                        help="compare with this carom binary, run side by side, row by row")
    args = parser.parse_args()
    callgrind = not args.no_callgrind and shutil.which("valgrind") is not None
    baseline = baseline_rates()
    sizes = [10**3, 10**4, 10**5] + ([] if args.quick else [10**6])
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        reference = measure(args.carom, folder, 2000, 0.5, 2000, engine="reference")
        fast_2000 = measure(args.carom, folder, 2000, 0.5, 2_000_000)
        speedup = fast_2000["collisions_per_second"] / reference["collisions_per_second"]
        print(f"N = 2000, eta = 0.5: reference {reference['collisions_per_second']:.4g}/s, "
              f"fast {fast_2000['collisions_per_second']:.4g}/s: speedup {speedup:.0f}x",
              flush=True)
        versus = "vs " + os.path.basename(args.versus) \
            if args.versus else "vs baseline"
        print(f"| particles | N | eta | collisions/s | {versus} | instructions/collision "
              "| bytes/particle | collisions | seconds | rate / rate(N=10^4) |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        base = {}
        cases = [(2, eta, n) for eta in (0.3, 0.5, 0.7) for n in sizes]
        cases += [(3, eta, n) for eta in (0.3, 0.45) for n in sizes if n >= 10**4]
        for dim, eta, n in cases:
            collisions = min(50 * n, 4_000_000)
            if args.versus:
                runs = [(measure(args.carom, folder, n, eta, collisions, dim=dim),
                         measure(args.versus, folder, n, eta, collisions, dim=dim))
                        for _ in range(2)]
                row = max((new for new, _ in runs), key=lambda r: r["collisions_per_second"])
                then = max(old["collisions_per_second"] for _, old in runs)
            else:
                row = measure(args.carom, folder, n, eta, collisions, dim=dim)
                then = baseline.get((dim, n, eta))
            if n == 10**4:
                base[dim, eta] = row["collisions_per_second"]
            ratio = (row["collisions_per_second"] / base[dim, eta]) if (dim, eta) in base else None
            row["rate_over_n10000"] = ratio
            row["rate_over_baseline"] = row["collisions_per_second"] / then if then else None
            counted = callgrind and n == 10**4 and (dim, eta) in ((2, 0.5), (2, 0.7), (3, 0.45))
            row["instructions_per_collision"] = (
                instructions_per_collision(args.carom, folder, n, eta, dim) if counted else None)
            row["baseline_instructions_per_collision"] = (
                instructions_per_collision(args.versus, folder, n, eta, dim)
                if counted and args.versus else None)
            rows.append(row)
            counts = shown(row["instructions_per_collision"], ",.0f")
            if row["baseline_instructions_per_collision"]:
                counts += f" ({row['baseline_instructions_per_collision']:,.0f})"
            print(f"| {'disks' if dim == 2 else 'spheres'} | {n} | {eta} "
                  f"| {row['collisions_per_second']:.4g} | {shown(row['rate_over_baseline'], '.2f')} "
                  f"| {counts} "
                  f"| {row['bytes_per_particle']:.0f} | {row['collisions']} | {row['seconds']:.2f} "
                  f"| {shown(ratio, '.2f')} |", flush=True)
    result = {"name": args.name, "date": datetime.datetime.now().isoformat(timespec="seconds"),
              "machine": platform.node(), "cpu_count": os.cpu_count(),
              "versus": args.versus, "reference_n2000": reference, "fast_n2000": fast_2000,
              "speedup_over_reference_n2000": speedup, "runs": rows}
    path = os.path.join(HERE, "results", f"{args.name}.json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path + ".tmp", "w") as f:
        json.dump(result, f, indent=2)
    os.replace(path + ".tmp", path)
    print(f"wrote {os.path.relpath(path)}")


if __name__ == "__main__":
    main()
