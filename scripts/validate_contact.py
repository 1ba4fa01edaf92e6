#!/usr/bin/env python3
"""Compares Z from the contact value of g(r) (carom analyze) with the collision virial of a run.

Regenerates the contact-theorem table in docs/validation.md:
    /usr/bin/python3 scripts/validate_contact.py [--carom build/carom] [--dim 2|3] [--seed 1]
For hard particles the pressure is fixed by the pair distribution at contact,
Z = 1 + 2 eta g(d+) (disks) or 1 + 4 eta g(d+) (spheres). Each state point: `carom init`
(periodic box, kT = 1; a lattice start above eta = 0.4 for disks, 0.25 for spheres), an elastic
run that equilibrates for --equilibrate time units and measures for --measure more, dumping a GSD
frame every --every, then `carom analyze` over the frames of the measurement window. Z from the
contact value and Z from the collision virial (the run's summary) come from the same window of
the same run. Disks are also compared with Henderson's equation of state, spheres with the
Kolafa-Labik-Malijevsky one. Prints a Markdown table, then a few diagnostic lines: the virial Z
over the first and the second half of the window (it must have settled) and, for disks, the
global hexatic order |<psi6>| (near 0 once the lattice start has melted).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True  # no __pycache__ left in scripts/ by the import below
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from validate_eos import henderson, kolafa_labik_malijevsky  # noqa: E402

# (dim, eta, N)
STATE_POINTS = [(2, 0.30, 4096), (2, 0.50, 4096), (2, 0.65, 4096),
                (3, 0.20, 4000), (3, 0.35, 4000), (3, 0.45, 4000)]


def measure(args, dim, n, eta, folder):
    equilibrate = args.equilibrate
    if equilibrate is None:
        equilibrate = 100.0 if dim == 2 else 20.0
    name = f"{dim}d-{eta}"
    start = os.path.join(folder, f"start-{name}.txt")
    summary = os.path.join(folder, f"summary-{name}.json")
    log = os.path.join(folder, f"log-{name}.csv")
    trajectory = os.path.join(folder, f"run-{name}.gsd")
    analysis = os.path.join(folder, f"analysis-{name}.json")
    began = time.monotonic()
    subprocess.run([args.carom, "init", "--dim", str(dim), "--n", str(n), "--phi", str(eta),
                    "--boundary", "periodic", "--seed", str(args.seed), "-o", start], check=True)
    subprocess.run([args.carom, "run", start, str(equilibrate + args.measure), "--rule", "elastic",
                    "--boundary", "periodic", "--equilibrate", str(equilibrate),
                    "--dump", trajectory, "--every", str(args.every),
                    "--log", log, "--log-every", str(args.every), "--summary", summary,
                    "-o", os.devnull, "--quiet"], check=True)
    command = [args.carom, "analyze", trajectory, "--equilibrate", str(equilibrate), "-o", analysis]
    if args.contact_width is not None:
        command += ["--contact-width", str(args.contact_width)]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    seconds = time.monotonic() - began
    with open(summary) as f:
        s = json.load(f)
    with open(analysis) as f:
        a = json.load(f)
    # Z over each --every interval of the measurement window, from the run's time series.
    with open(log) as f:
        window = [float(row["Z"]) for row in csv.DictReader(f)
                  if row["Z"] and float(row["time"]) > equilibrate + 1e-9]
    half = len(window) // 2
    halves = (sum(window[:half]) / half, sum(window[half:]) / (len(window) - half))
    psi6 = (a.get("psi6") or {}).get("global")
    return s, a, seconds, halves, (sum(psi6) / len(psi6) if psi6 else None)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--dim", type=int, choices=[2, 3], help="only disks or only spheres")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--equilibrate", type=float, help="default 100 (disks) or 20 (spheres)")
    parser.add_argument("--measure", type=float, default=150.0, help="length of the window")
    parser.add_argument("--every", type=float, default=0.5, help="time between frames")
    parser.add_argument("--contact-width", type=float, help="passed to carom analyze (d / 10)")
    args = parser.parse_args()
    points = [p for p in STATE_POINTS if args.dim in (None, p[0])]
    print("| dim | eta | N | frames | g(d+) | Z contact | Z virial | contact vs virial "
          "| Z published | wall time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    diagnostics = []
    with tempfile.TemporaryDirectory() as folder:
        for dim, eta, n in points:
            s, a, seconds, halves, psi6 = measure(args, dim, n, eta, folder)
            contact = a["rdf"]["contact"]
            z_virial = s["compressibility_factor"]
            published, name = ((henderson(eta), "Henderson") if dim == 2
                               else (kolafa_labik_malijevsky(eta), "KLM"))
            print(f"| {dim} | {eta:.2f} | {s['n']} | {a['frames']['count']} | {contact['g']:.4f} "
                  f"| {contact['Z']:.4f} | {z_virial:.4f} "
                  f"| {100 * (contact['Z'] / z_virial - 1):+.2f}% "
                  f"| {published:.4f} ({name}) | {seconds:.0f} s |", flush=True)
            change = 100 * (halves[1] / halves[0] - 1)
            line = (f"{dim}D eta {eta:.2f}: virial Z over the first / second half of the window "
                    f"{halves[0]:.4f} / {halves[1]:.4f} ({change:+.2f}%)")
            if psi6 is not None:
                line += f"; mean global |psi6| {psi6:.3f}"
            diagnostics.append(line)
    print()
    for line in diagnostics:
        print(line)


if __name__ == "__main__":
    main()
