#!/usr/bin/env python3
"""Measures the hard-disk or hard-sphere equation of state Z(eta) with carom against theory.

Regenerates the equation-of-state tables in docs/validation.md:
    python3 scripts/validate_eos.py [--dim 2|3] [--sampler md|ecmc] [--carom build/carom] [--n N]
Each packing fraction: `carom init` (periodic box, kT = 1), then an elastic run (or event chains,
--sampler ecmc) that equilibrates for --equilibrate time units and measures for --measure more.
Prints a Markdown table.
Disks are compared with Henderson's equation of state and reference values of an independent
code, spheres with the Kolafa-Labik-Malijevsky equation of state.
"""
import argparse
import json
import math
import os
import subprocess
import tempfile

# Reference values for disks measured with an independent code.
DISK_REFERENCE = {0.30: 2.063, 0.50: 4.107, 0.60: 6.456, 0.65: 8.41}
SPHERE_PACKINGS = [0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45]


def henderson(eta):
    return (1 + eta**2 / 8) / (1 - eta) ** 2 - 0.043 * eta**4 / (1 - eta) ** 3


def kolafa_labik_malijevsky(eta):
    return (1 + eta + eta**2 - 2 / 3 * eta**3 * (1 + eta)) / (1 - eta) ** 3


def measure(carom, dim, n, eta, seed, equilibrate, length, folder, sampler):
    start = os.path.join(folder, f"start-{eta}.txt")
    summary = os.path.join(folder, f"summary-{eta}.json")
    subprocess.run([carom, "init", "--dim", str(dim), "--n", str(n), "--phi", str(eta),
                    "--boundary", "periodic", "--seed", str(seed), "-o", start], check=True)
    how = ["--rule", "elastic"] if sampler == "md" else ["--sampler", "ecmc", "--seed", str(seed)]
    subprocess.run([carom, "run", start, str(equilibrate + length), *how,
                    "--boundary", "periodic", "--equilibrate", str(equilibrate), "--format", "csv",
                    "-o", os.devnull, "--summary", summary, "--quiet"], check=True)
    with open(summary) as f:
        return json.load(f)


def chains_table(args, n, equilibrate, length, theory, packings, name):
    """Event chains: Z with its standard error over the window's 20 intervals, and along each
    axis, against the equation of state."""
    print(f"| eta | Z (event chains) | Z {name} | difference | in errors | Z along x, y[, z] | N "
          f"| lifts | lifts/s |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for eta in packings:
            s = measure(args.carom, args.dim, n, eta, args.seed, equilibrate, length, folder,
                        "ecmc")
            z, error = s["compressibility_factor"], s["compressibility_factor_error"]
            expected = theory(eta)
            axes = ", ".join(f"{v:.4f}" for v in s["directional_compressibility_factor"])
            print(f"| {eta:.2f} | {z:.4f} +- {error:.4f} | {expected:.4f} "
                  f"| {100 * (z / expected - 1):+.2f}% | {(z - expected) / error:+.1f} | {axes} "
                  f"| {s['n']} | {s['lifts']} | {s['events_per_second']:.3g} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--dim", type=int, choices=[2, 3], default=2)
    parser.add_argument("--n", type=int, help="default 4096 disks or 4000 spheres (10^3 FCC cells)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--equilibrate", type=float, help="default 100 (disks) or 20 (spheres)")
    parser.add_argument("--measure", type=float, help="default 200 (disks) or 100 (spheres)")
    parser.add_argument("--sampler", choices=["md", "ecmc"], default="md",
                        help="dynamics, or event-chain Monte Carlo (its own table: Z with its "
                             "error, lifts)")
    args = parser.parse_args()
    disks = args.dim == 2
    n = args.n or (4096 if disks else 4000)
    equilibrate = args.equilibrate or (100.0 if disks else 20.0)
    length = args.measure or (200.0 if disks else 100.0)
    theory = henderson if disks else kolafa_labik_malijevsky
    packings = sorted(DISK_REFERENCE) if disks else SPHERE_PACKINGS
    name = "Henderson" if disks else "KLM"
    if args.sampler == "ecmc":
        chains_table(args, n, equilibrate, length, theory, packings, name)
        return
    print(f"| eta | Z measured | Z {name} | error |" + (" Z reference |" if disks else "")
          + " Z - 1 from collision rate | N | collisions | energy drift | events/s |")
    print("|---|---|---|---|---|---|---|---|---|" + ("---|" if disks else ""))
    with tempfile.TemporaryDirectory() as folder:
        for eta in packings:
            s = measure(args.carom, args.dim, n, eta, args.seed, equilibrate, length, folder,
                        "md")
            z = s["compressibility_factor"]
            expected = theory(eta)
            # Z - 1 = omega sigma sqrt(pi m / kT) / (2 D) with sigma = m = 1: the mean momentum a
            # collision transfers along the line of centres is sqrt(pi m kT) in any dimension.
            from_rate = s["collision_rate"] * math.sqrt(math.pi / s["temperature"]) / (2 * args.dim)
            drift = abs(s["kinetic_energy_final"] / s["kinetic_energy_initial"] - 1)
            reference = f" {DISK_REFERENCE[eta]} |" if disks else ""
            print(f"| {eta:.2f} | {z:.4f} | {expected:.4f} | {100 * (z / expected - 1):+.2f}% |"
                  f"{reference} {from_rate:.4f} (Z - 1 = {z - 1:.4f}) | {s['n']} "
                  f"| {s['pair_collisions']} | {drift:.1e} | {s['events_per_second']:.3g} |",
                  flush=True)


if __name__ == "__main__":
    main()
