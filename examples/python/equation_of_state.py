#!/usr/bin/env python3
"""The hard-disk equation of state Z(eta) measured with carom, against Henderson's.

    /usr/bin/python3 examples/python/equation_of_state.py [--n 1024] [-o equation_of_state.png]

For each packing fraction: carom.init (a periodic box, kT = 1, elastic collisions), a run to
equilibrate, then a measured run; Z = PA/NkT comes from the collision virial. Prints a table and
plots the points on Henderson's curve with matplotlib (python3-matplotlib).
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt
import numpy as np

import carom


def henderson(eta):
    return (1 + eta**2 / 8) / (1 - eta) ** 2 - 0.043 * eta**4 / (1 - eta) ** 3


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1024, help="disks (default 1024)")
    parser.add_argument("--equilibrate", type=float, default=20.0)
    parser.add_argument("--measure", type=float, default=80.0)
    parser.add_argument("-o", "--output", default="equation_of_state.png")
    args = parser.parse_args()

    # Up to 0.65: nearer the liquid-hexatic transition (about 0.70) Henderson is no longer exact.
    packings = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65]
    measured = []
    print("  eta   Z carom   Z Henderson   collisions")
    for eta in packings:
        sim = carom.init(n=args.n, phi=eta, seed=1, boundary="periodic", rule="elastic")
        sim.run(args.equilibrate)
        sim.reset_measurement()
        sim.run(args.equilibrate + args.measure)
        o = sim.observables()
        measured.append(o["compressibility_factor"])
        print(f"  {eta:.2f}  {measured[-1]:8.4f}  {henderson(eta):11.4f}   {o['pair_collisions']}")

    curve = np.linspace(0.0, 0.7, 200)
    plt.figure(figsize=(5, 3.6))
    plt.plot(curve, henderson(curve), color="0.4", label="Henderson (1975)")
    plt.plot(packings, measured, "o", color="tab:red", label=f"carom, N = {args.n}")
    plt.xlabel("packing fraction $\\eta$")
    plt.ylabel("$Z = PA / NkT$")
    plt.title("Hard disks: equation of state")
    plt.legend()
    plt.tight_layout()
    plt.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
