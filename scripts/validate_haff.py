#!/usr/bin/env python3
"""Haff's law: a dilute gas of inelastic hard spheres (or disks) cools as T(t) = T0 / (1 + t/tau)^2.

Regenerates the Haff's-law table in docs/validation.md and, with --plot FILE.svg, the figure of
the README:
    python3 scripts/validate_haff.py [--carom build/carom] [--dim 3] [--n 4000] [--phi 0.05]
                                     [--restitution 0.9 0.95] [--plot docs/images/haff.svg]
Each restitution: `carom init` (periodic box, kT = 1), then `carom run --restitution E --log`.
The theory (homogeneous cooling state, Brilliantov and Poeschel, Kinetic Theory of Granular
Gases, 2004): dT/dt = -zeta T with the cooling rate zeta = omega (1 - e^2) / d (1 + 3 a2 / 16),
omega = the Enskog collision frequency (4 sqrt(pi) n sigma^2 chi sqrt(T / m) for spheres,
2 sqrt(pi) n sigma chi sqrt(T / m) for disks, chi the contact value of Carnahan-Starling or
Henderson), a2 van Noije and Ernst's Sonine coefficient; so tau = 2 / zeta(T0). The gas starts
from Maxwell-Boltzmann velocities, so the first collision times relax to the cooling state.
"""
import argparse
import csv
import math
import os
import subprocess
import tempfile


def contact_value(phi, dim):
    if dim == 3:
        return (1 - phi / 2) / (1 - phi) ** 3
    return (1 - 7 * phi / 16) / (1 - phi) ** 2


def sonine_a2(e, dim):
    return 16 * (1 - e) * (1 - 2 * e * e) / (9 + 24 * dim - e * (41 - 8 * dim) + 30 * (1 - e) * e * e)


def haff_tau(phi, e, dim, kT0=1.0, sigma=1.0, mass=1.0):
    if dim == 3:
        n = 6 * phi / (math.pi * sigma**3)
        omega = 4 * math.sqrt(math.pi) * n * sigma**2 * contact_value(phi, 3) * math.sqrt(kT0 / mass)
    else:
        n = 4 * phi / (math.pi * sigma**2)
        omega = 2 * math.sqrt(math.pi) * n * sigma * contact_value(phi, 2) * math.sqrt(kT0 / mass)
    zeta = omega * (1 - e * e) / dim * (1 + 3 * sonine_a2(e, dim) / 16)
    return 2 / zeta


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--dim", type=int, default=3)
    parser.add_argument("--n", type=int, default=4000)
    parser.add_argument("--phi", type=float, default=0.05)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--restitution", type=float, nargs="*", default=[0.9, 0.95])
    parser.add_argument("--taus", type=float, default=10.5, help="how many tau to run for")
    parser.add_argument("--plot", help="write the figure (SVG) here")
    args = parser.parse_args()
    curves = {}
    print("| e | tau | t / tau | kT, carom | kT, Haff | carom / Haff |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        start = os.path.join(tmp, "start.txt")
        subprocess.run([args.carom, "init", "--dim", str(args.dim), "--n", str(args.n), "--phi",
                        str(args.phi), "--boundary", "periodic", "--seed", str(args.seed), "-o",
                        start], check=True)
        for e in args.restitution:
            tau = haff_tau(args.phi, e, args.dim)
            end = args.taus * tau
            log = os.path.join(tmp, f"log_{e}.csv")
            subprocess.run([args.carom, "run", start, repr(end), "--restitution", str(e), "--log",
                            log, "--log-every", repr(tau / 20), "-o", os.devnull], check=True,
                           stderr=subprocess.DEVNULL)
            with open(log) as f:
                rows = [(float(r["time"]), float(r["temperature"])) for r in csv.DictReader(f)]
            curves[e] = (tau, rows)
            kT0 = rows[0][1]
            for k, (t, kT) in enumerate(rows):  # a row every tau / 20 from t = 0
                if k in (10, 20, 40, 100, 200):
                    theory = kT0 / (1 + t / tau) ** 2
                    print(f"| {e} | {tau:.3f} | {t / tau:.1f} | {kT:.5f} | {theory:.5f} | "
                          f"{kT / theory:.4f} |", flush=True)
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        matplotlib.rcParams["svg.hashsalt"] = "carom"  # the same bytes on every run
        fig, ax = plt.subplots(figsize=(6, 4))
        for e, (tau, rows) in curves.items():
            t = [row[0] for row in rows]
            ax.loglog([1 + x / tau for x in t][::4], [row[1] for row in rows][::4], "o", ms=4,
                      label=f"carom, e = {e} (tau = {tau:.1f})")
        x = [10 ** (k / 50) for k in range(0, 52)]
        ax.loglog(x, [1 / v**2 for v in x], "k-", lw=1, label="Haff: kT0 / (1 + t / tau)^2")
        ax.set_xlabel("1 + t / tau (tau from the Enskog collision frequency)")
        ax.set_ylabel("kT")
        ax.set_title(f"Cooling of {args.n} inelastic {'spheres' if args.dim == 3 else 'disks'}, "
                     f"packing {args.phi}")
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot, metadata={"Date": None})


if __name__ == "__main__":
    main()
