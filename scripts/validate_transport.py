#!/usr/bin/env python3
"""Measures the transport coefficients of hard spheres with `carom run --transport` against
Enskog's theory.

Regenerates the transport table in docs/validation.md:
    python3 scripts/validate_transport.py [--carom build/carom] [--n N] [--seed 1]
Each packing fraction: `carom init` (periodic cube, kT = 1, diameter 1, mass 1), then an elastic
run that equilibrates for --equilibrate time units and measures for --measure more. Prints a
Markdown table of D (raw and with Yeh and Hummer's finite-size correction), the shear viscosity
and the thermal conductivity, each with its error from 10 blocks and its ratio to Enskog's value.
"""
import argparse
import json
import os
import subprocess
import tempfile

PACKINGS = [0.10, 0.20, 0.30, 0.40, 0.45]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--n", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--equilibrate", type=float, default=20.0)
    parser.add_argument("--measure", type=float, default=400.0)
    parser.add_argument("--phi", type=float, nargs="*", default=PACKINGS)
    args = parser.parse_args()
    print("| phi | D | D, Yeh-Hummer | D_YH / D_E | eta | eta / eta_E | lambda | lambda / lambda_E |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for phi in args.phi:
            start = os.path.join(tmp, f"start_{phi}.txt")
            summary = os.path.join(tmp, f"summary_{phi}.json")
            subprocess.run([args.carom, "init", "--dim", "3", "--n", str(args.n), "--phi", str(phi),
                            "--boundary", "periodic", "--seed", str(args.seed), "-o", start],
                           check=True)
            end = args.equilibrate + args.measure
            subprocess.run([args.carom, "run", start, str(end), "--equilibrate",
                            str(args.equilibrate), "--transport", "--summary", summary, "-o",
                            os.devnull], check=True, stderr=subprocess.DEVNULL)
            t = json.load(open(summary))["transport"]
            d, d_yh = t["self_diffusion"], t["self_diffusion_yeh_hummer"]
            eta, lam = t["shear_viscosity"], t["thermal_conductivity"]
            print(f"| {phi:.2f} | {d:.4f} +- {t['self_diffusion_error']:.4f} | {d_yh:.4f} | "
                  f"{d_yh / t['enskog_self_diffusion']:.3f} | "
                  f"{eta:.3f} +- {t['shear_viscosity_error']:.3f} | "
                  f"{eta / t['enskog_shear_viscosity']:.3f} | "
                  f"{lam:.3f} +- {t['thermal_conductivity_error']:.3f} | "
                  f"{lam / t['enskog_thermal_conductivity']:.3f} |", flush=True)


if __name__ == "__main__":
    main()
