#!/usr/bin/env python3
"""Measures jamming densities of carom compress (Lubachevsky-Stillinger) against the literature.

Regenerates the compression table in docs/validation.md:
    /usr/bin/python3 scripts/validate_compress.py [--carom build/carom] [--quick] [--jobs 1]
(the default takes about 14 minutes on 2 cores; --rates, --seeds, --slow-rates ... to vary)
Three systems, each grown with `carom compress --jam` (Z = PV/NkT past 1e12) in a periodic box
from a random start (random sequential addition, kT = 1):
  * 3D equal spheres, N = 1000 (--n3), at several growth rates (--rates) and seeds (--seeds), from
    phi = 0.2: phi_J against Skoge, Donev, Stillinger and Torquato, PRE 74, 041127 (2006);
  * 2D 50:50 bidisperse disks, size ratio 1.4, N = 1000 (--n2), from phi = 0.3 with every other
    radius shrunk by 1/1.4: phi_J against O'Hern, Silbert, Liu and Nagel, PRE 68, 011306 (2003);
  * 3D equal spheres, N = 500 (--slow-n), compressed slowly (--slow-rates): they crystallise.
Every packing is read back and checked independently with numpy: the largest overlap over every
pair (minimum image), and for spheres the global Steinhardt bond order Q6 over the bonds shorter
than 1.2 contact distances (FCC 0.575, HCP 0.485, an amorphous packing of N = 1000 a few 0.01).
The Q6 code is first checked on carom's own FCC lattice. Prints Markdown tables.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

SIZE_RATIO = 1.4
Q6_CUTOFF = 1.2  # bonds: centre distance below 1.2 (r_i + r_j)


def read_classic(path):
    """The positions, radii and box of a classic start file (comments and blank lines skipped)."""
    with open(path) as f:
        rows = [line.split() for line in f if line.strip() and not line.lstrip().startswith("#")]
    n = int(rows[0][0])
    radius = float(rows[1][0])
    box = np.array([float(v) for v in rows[2]])
    dim = len(box)
    data = rows[3:3 + n]
    assert len(data) == n, f"{path}: {len(data)} particle lines, expected {n}"
    positions = np.array([[float(v) for v in row[:dim]] for row in data])
    radii = np.array([float(row[2 * dim]) if len(row) > 2 * dim else radius for row in data])
    return positions, radii, box


def pair_geometry(positions, box):
    """Minimum-image separation vectors and distances of every pair i < j."""
    i, j = np.triu_indices(len(positions), k=1)
    delta = positions[j] - positions[i]
    delta -= box * np.round(delta / box)
    return i, j, delta, np.sqrt((delta**2).sum(axis=1))


def largest_overlap(radii, i, j, distance):
    """max over pairs of (r_i + r_j - |r_ij|) / (r_i + r_j): negative when no pair overlaps."""
    contact = radii[i] + radii[j]
    return float(((contact - distance) / contact).max())


def q6_global(radii, i, j, delta, distance):
    """Global Steinhardt Q6 over the bonds shorter than Q6_CUTOFF contact distances, and the mean
    number of such neighbours. By the addition theorem sum_m |<Y6m>|^2 = 13 / (4 pi) <P6(u.u')>
    over pairs of bonds, so Q6^2 = the mean over bond pairs of P6(cos angle): no harmonics."""
    bond = distance < Q6_CUTOFF * (radii[i] + radii[j])
    units = delta[bond] / distance[bond][:, None]
    total = 0.0
    for start in range(0, len(units), 2000):
        x = units[start:start + 2000] @ units.T
        x2 = x * x
        total += float((((231 * x2 - 315) * x2 + 105) * x2 - 5).sum()) / 16
    return math.sqrt(max(total, 0.0)) / len(units), 2 * len(units) / len(radii)


def analyse(path):
    positions, radii, box = read_classic(path)
    i, j, delta, distance = pair_geometry(positions, box)
    checks = {"overlap": largest_overlap(radii, i, j, distance),
              "phi_file": float(sum(math.pi * r**2 if len(box) == 2 else 4 / 3 * math.pi * r**3
                                    for r in radii) / np.prod(box))}
    if len(box) == 3:
        checks["q6"], checks["neighbours"] = q6_global(radii, i, j, delta, distance)
    return checks


def make_bidisperse(path):
    """Every other radius shrunk by 1 / SIZE_RATIO: a 50:50 mixture (shrinking makes no overlap)."""
    with open(path) as f:
        lines = f.read().split("\n")
    radius = float(lines[1])
    n = int(lines[0])
    for k in range(n):
        small = k % 2 == 1
        lines[3 + k] = f"{lines[3 + k]} {radius / SIZE_RATIO if small else radius!r}"
    with open(path, "w") as f:
        f.write("\n".join(lines))


def compress(carom, folder, label, dim, n, phi, seed, rate, bidisperse=False):
    start = os.path.join(folder, f"start-{label}.txt")
    out = os.path.join(folder, f"jammed-{label}.txt")
    summary = os.path.join(folder, f"summary-{label}.json")
    subprocess.run([carom, "init", "--dim", str(dim), "--n", str(n), "--phi", str(phi), "--random",
                    "--boundary", "periodic", "--seed", str(seed), "-o", start], check=True)
    if bidisperse:
        make_bidisperse(start)
    began = time.monotonic()
    subprocess.run([carom, "compress", start, "--jam", "--rate", str(rate), "--boundary",
                    "periodic", "-o", out, "--summary", summary, "--quiet"], check=True)
    seconds = time.monotonic() - began
    with open(summary) as f:
        s = json.load(f)
    s["seconds"] = seconds
    s.update(analyse(out))
    return s


def row(name, n, rate, runs, reference):
    phis = [s["packing_fraction"] for s in runs]
    mean = statistics.mean(phis)
    spread = f" ± {statistics.stdev(phis):.4f}" if len(phis) > 1 else ""
    q6 = " ".join(f"{s['q6']:.3f}" for s in runs) if "q6" in runs[0] else "-"
    seconds = sum(s["seconds"] for s in runs)
    print(f"| {name} | {n} | {rate:g} | {' '.join(f'{p:.4f}' for p in phis)} | {mean:.4f}{spread} "
          f"| {q6} | {max(s['overlap'] for s in runs):.1e} "
          f"| {max(s['compressibility_factor'] for s in runs):.1e} "
          f"| {statistics.mean(s['events'] for s in runs):.3g} | {seconds:.0f} s | {reference} |",
          flush=True)


def numbers(text, kind=float):
    return [kind(v) for v in text.split(",") if v.strip()]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--n3", type=int, default=1000, help="spheres of the rate scan")
    parser.add_argument("--rates", default="0.1,0.03,0.01", help="3D growth rates ('' skips)")
    parser.add_argument("--seeds", default="1,2,3", help="seeds of every 3D rate")
    parser.add_argument("--n2", type=int, default=1000, help="bidisperse disks")
    parser.add_argument("--rates2", default="0.1,0.01", help="2D growth rates ('' skips)")
    parser.add_argument("--seeds2", default="1,2,3", help="seeds of every 2D rate")
    parser.add_argument("--slow-n", type=int, default=500, help="spheres of the slow compressions")
    parser.add_argument("--slow-rates", default="0.001,0.0003", help="('' skips)")
    parser.add_argument("--slow-seeds", default="1", help="seeds of every slow rate")
    parser.add_argument("--jobs", type=int, default=1, help="compressions run at once")
    parser.add_argument("--quick", action="store_true",
                        help="seed 1, 3D rates 0.1 and 0.01, 2D 0.1, no slow compression (~1 min)")
    args = parser.parse_args()
    rates, rates2, slow_rates = (numbers(args.rates), numbers(args.rates2),
                                 numbers(args.slow_rates))
    seeds, seeds2, slow_seeds = (numbers(args.seeds, int), numbers(args.seeds2, int),
                                 numbers(args.slow_seeds, int))
    if args.quick:
        seeds = seeds2 = [1]
        rates, rates2, slow_rates = [0.1, 0.01], [0.1], []
    began = time.monotonic()
    with tempfile.TemporaryDirectory() as folder:
        # The Q6 code on a perfect FCC lattice (N = 4 5^3 fills the periodic cube): 0.5745.
        fcc = os.path.join(folder, "fcc.txt")
        subprocess.run([args.carom, "init", "--dim", "3", "--n", "500", "--phi", "0.74",
                        "--lattice", "--boundary", "periodic", "-o", fcc], check=True)
        check = analyse(fcc)
        print(f"Q6 of carom init's FCC lattice (N = 500, phi = 0.74): {check['q6']:.4f} "
              f"({check['neighbours']:.2f} neighbours; exact 0.5745, 12)\n", flush=True)

        jobs = []  # (group key, label, dim, n, phi, seed, rate, bidisperse)
        for rate in rates:
            for seed in seeds:
                jobs.append((("3D", args.n3, rate), f"3d-{rate}-{seed}", 3, args.n3, 0.2, seed,
                             rate, False))
        for rate in rates2:
            for seed in seeds2:
                jobs.append((("2D", args.n2, rate), f"2d-{rate}-{seed}", 2, args.n2, 0.3, seed,
                             rate, True))
        for rate in slow_rates:
            for seed in slow_seeds:
                jobs.append((("3D slow", args.slow_n, rate), f"slow-{rate}-{seed}", 3,
                             args.slow_n, 0.2, seed, rate, False))
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = [(key, pool.submit(compress, args.carom, folder, *rest))
                       for key, *rest in jobs]
            results = {}
            for key, future in futures:
                results.setdefault(key, []).append(future.result())

    references = {"3D": "Skoge et al. 2006: ~0.64, denser as the rate falls",
                  "2D": "O'Hern et al. 2003: 0.84 (N -> inf 0.842)",
                  "3D slow": "crystal: toward 0.74 (FCC/HCP)"}
    names = {"3D": "3D spheres", "2D": "2D disks 50:50, 1:1.4", "3D slow": "3D spheres, slow"}
    print("| system | N | rate G | phi_J per seed | phi_J mean ± sd | Q6 per seed "
          "| largest overlap | Z at stop | events (mean) | wall time | literature |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for key, runs in results.items():
        row(names[key[0]], key[1], key[2], runs, references[key[0]])
    everything = [s for runs in results.values() for s in runs]
    spheres = [(k, r) for k, r in results.items() if k[0] != "2D"]
    print()
    print(f"{len(everything)} packings, status 'jammed': "
          f"{sum(s['status'] == 'jammed' for s in everything)}; packing fraction of the file vs "
          f"the summary, largest difference "
          f"{max(abs(s['phi_file'] - s['packing_fraction']) for s in everything):.1e}; "
          f"mean neighbours within {Q6_CUTOFF} contact distances (3D, by rate): "
          + ", ".join(f"{k[2]:g}: {statistics.mean(s['neighbours'] for s in r):.2f}"
                      for k, r in spheres)
          + f"; total {time.monotonic() - began:.0f} s")


if __name__ == "__main__":
    main()
