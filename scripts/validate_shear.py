#!/usr/bin/env python3
"""Measures the shear viscosity of hard spheres under Lees-Edwards shear (`carom run --shear`)
against the Einstein-Helfand value of an equilibrium run (`carom run --transport`).

Regenerates the shear table in docs/validation.md and the README's figure:
    python3 scripts/validate_shear.py [--carom build/carom] [--n N] [--plot FILE.svg]
At packing fraction --phi (0.3): `carom init` (periodic cube, kT = 1, diameter 1, mass 1); an
elastic equilibrium run with --transport; then at each shear rate a run from the streaming
profile (--velocity-profile) held at kT = 1 relative to it by velocity rescaling, often enough
that the viscous heating between two rescalings stays near a per cent. Each run equilibrates for
--equilibrate time units and measures for --measure more (the run at rest for --measure-at-rest,
as the Einstein-Helfand estimate converges more slowly). Prints a Markdown table of the shear
stress and viscosity with their errors (the spread over 20 intervals) and the viscosity's ratio
to the equilibrium one; --plot draws the viscosity against the rate.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import tempfile

RATES = [0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 4.0]


def run(carom, start, end, equilibrate, summary, options):
    subprocess.run([carom, "run", start, str(end), "--rule", "elastic", "--equilibrate",
                    str(equilibrate), "--summary", summary, "-q", "-o", os.devnull, *options],
                   check=True)
    return json.load(open(summary))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--n", type=int, default=1000)
    parser.add_argument("--phi", type=float, default=0.3)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--equilibrate", type=float, default=20.0)
    parser.add_argument("--measure", type=float, default=400.0)
    parser.add_argument("--measure-at-rest", type=float, default=3200.0)
    parser.add_argument("--rates", type=float, nargs="*", default=RATES)
    parser.add_argument("--plot", help="draw the viscosity against the shear rate to this file")
    args = parser.parse_args()
    end = args.equilibrate + args.measure
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(2) as pool:
        start = os.path.join(tmp, "start.txt")
        subprocess.run([args.carom, "init", "--dim", "3", "--n", str(args.n), "--phi",
                        str(args.phi), "--boundary", "periodic", "--seed", str(args.seed), "-o",
                        start], check=True)
        equilibrium = pool.submit(run, args.carom, start,
                                  args.equilibrate + args.measure_at_rest, args.equilibrate,
                                  os.path.join(tmp, "equilibrium.json"), ["--transport"])
        sheared = [pool.submit(run, args.carom, start, end, args.equilibrate,
                               os.path.join(tmp, f"shear_{rate}.json"),
                               ["--shear", str(rate), "--velocity-profile", "--kT", "1",
                                "--thermostat", "rescale", "--thermostat-every",
                                str(min(0.1, 0.02 / rate))])
                   for rate in args.rates]
        t = equilibrium.result()["transport"]
        eta, eta_error = t["shear_viscosity"], t["shear_viscosity_error"]
        print(f"Einstein-Helfand (no shear): eta = {eta:.4f} +- {eta_error:.4f} "
              f"(Enskog {t['enskog_shear_viscosity']:.4f})\n")
        print("| shear rate | shear stress | eta | eta / eta_EH | kT |")
        print("|---|---|---|---|---|")
        points = []
        for rate, future in zip(args.rates, sheared):
            s = future.result()
            shear = s["shear"]
            points.append((rate, shear["shear_viscosity"], shear["shear_viscosity_error"]))
            print(f"| {rate:g} | {shear['shear_stress']:.4f} +- {shear['shear_stress_error']:.4f} "
                  f"| {shear['shear_viscosity']:.4f} +- {shear['shear_viscosity_error']:.4f} | "
                  f"{shear['shear_viscosity'] / eta:.3f} | {s['temperature']:.4f} |", flush=True)
    if args.plot:
        plot(args.plot, points, eta, eta_error, t["enskog_shear_viscosity"], args.phi)


def plot(path, points, eta, eta_error, enskog, phi):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(6, 4))
    rates = [p[0] for p in points]
    axes.axhspan(eta - eta_error, eta + eta_error, color="tab:blue", alpha=0.2)
    axes.axhline(eta, color="tab:blue", label="Einstein-Helfand, at rest")
    axes.axhline(enskog, color="gray", linestyle="--", label="Enskog")
    axes.errorbar(rates, [p[1] for p in points], yerr=[p[2] for p in points], fmt="o",
                  color="tab:red", label="Lees-Edwards shear")
    axes.set_xscale("log")
    axes.set_xlabel(r"shear rate $\dot\gamma$ $[\sqrt{kT/m}/\sigma]$")
    axes.set_ylabel(r"shear viscosity $\eta$ $[\sqrt{mkT}/\sigma^2]$")
    axes.set_title(f"Hard spheres at packing fraction {phi}, kT = 1")
    axes.legend()
    figure.tight_layout()
    figure.savefig(path)


if __name__ == "__main__":
    main()
