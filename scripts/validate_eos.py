#!/usr/bin/env python3
"""Measures the hard-disk equation of state Z(eta) with carom and compares it with theory.

Regenerates the table in docs/validation.md:
    python3 scripts/validate_eos.py [--carom build/carom] [--n 4096] [--seed 1]
Each packing fraction: `carom init` (periodic box, kT = 1), then an elastic run that equilibrates
for --equilibrate time units and measures for --measure more. Prints a Markdown table.
"""
import argparse
import json
import math
import os
import subprocess
import tempfile

# Reference values measured with an independent code (issue #3).
REFERENCE = {0.30: 2.063, 0.50: 4.107, 0.60: 6.456, 0.65: 8.41}


def henderson(eta):
    return (1 + eta**2 / 8) / (1 - eta) ** 2 - 0.043 * eta**4 / (1 - eta) ** 3


def measure(carom, n, eta, seed, equilibrate, length, folder):
    start = os.path.join(folder, f"start-{eta}.txt")
    summary = os.path.join(folder, f"summary-{eta}.json")
    subprocess.run([carom, "init", "--n", str(n), "--phi", str(eta), "--boundary", "periodic",
                    "--seed", str(seed), "-o", start], check=True)
    subprocess.run([carom, "run", start, str(equilibrate + length), "--rule", "elastic",
                    "--boundary", "periodic", "--equilibrate", str(equilibrate), "--format", "csv",
                    "-o", os.devnull, "--summary", summary], check=True)
    with open(summary) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--n", type=int, default=4096)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--equilibrate", type=float, default=100.0)
    parser.add_argument("--measure", type=float, default=200.0)
    args = parser.parse_args()
    print("| eta | Z measured | Z Henderson | error | Z reference | Z - 1 from collision rate "
          "| N | collisions | events/s |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for eta in sorted(REFERENCE):
            s = measure(args.carom, args.n, eta, args.seed, args.equilibrate, args.measure, folder)
            z = s["compressibility_factor"]
            theory = henderson(eta)
            # Z - 1 = omega sigma sqrt(pi m / kT) / 4 with sigma = m = 1.
            from_rate = s["collision_rate"] * math.sqrt(math.pi / s["temperature"]) / 4
            print(f"| {eta:.2f} | {z:.4f} | {theory:.4f} | {100 * (z / theory - 1):+.2f}% "
                  f"| {REFERENCE[eta]} | {from_rate:.4f} (Z - 1 = {z - 1:.4f}) | {s['n']} "
                  f"| {s['pair_collisions']} | {s['events_per_second']:.3g} |", flush=True)


if __name__ == "__main__":
    main()
