#!/usr/bin/env python3
"""Measures how fast event chains (`--sampler ecmc`) and dynamics (EDMD) decorrelate dense hard
disks per CPU second: the global orientational order |psi6| and the pressure.

Regenerates the decorrelation table and figure in docs/validation.md:
    python3 scripts/decorrelation.py [--carom build/carom] [--phi 0.70 0.71 0.72] [--budget 120]
        [--plot docs/images/decorrelation.svg]
At each packing fraction: one common start (`carom init`, its default draw: a triangular lattice at
these densities) brought towards equilibrium by --equilibrate units of event chains; from its end
(the run's `--format json` state, written back as a classic start) each sampler runs for about
--budget CPU seconds (ECMC as it is; EDMD with Maxwell-Boltzmann velocities at kT = 1 and the
elastic rule), the length in time units set by a short timing run of the same sampler from the same
start. Each writes --frames GSD frames and --log rows at the same cadence. `carom analyze` gives
|psi6| of each frame (global: the modulus of the mean over the disks of psi6_j with their six
nearest neighbours); the log gives Z over each interval. For each series: its normalised
autocorrelation function and integrated autocorrelation time tau = 1 + 2 sum_k rho(k) (in
intervals; Sokal's automatic window, the smallest M with M >= 5 tau(M)), converted to time units
and then to CPU seconds through the run's CPU seconds per time unit (the user time of carom, frames
and log included). The table also gives Z over the whole run with its block-average error (the
summary's), how far apart its two halves are in errors, and the CPU seconds that error says Z +-
0.01 would take (CPU s x (error / 0.01)^2). A tau is resolved only when the series spans at least
50 tau and the window closed; otherwise the windowed estimate is given as a lower bound ("> tau").
A tau below one interval is given as "< interval". Prints a Markdown table.
"""
import argparse
import csv
import json
import math
import os
import resource
import subprocess
import tempfile

import numpy as np

SAMPLERS = ("ecmc", "md")
WINDOW_C = 5.0
RESOLVED_SPANS = 50.0


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime


def carom(binary, *arguments):
    """Runs carom and returns the user CPU seconds it took."""
    before = cpu_seconds()
    subprocess.run([binary, *map(str, arguments)], check=True, stdout=subprocess.DEVNULL)
    return cpu_seconds() - before


def sampler_options(sampler):
    if sampler == "ecmc":
        return ["--sampler", "ecmc"]
    return ["--kT", "1", "--rule", "elastic"]


def autocorrelation(x):
    """The normalised autocorrelation function rho(k), k = 0 .. n-1 (the biased estimator, 1/n)."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    f = np.fft.rfft(x - x.mean(), n=2 * n)
    c = np.fft.irfft(f * np.conjugate(f))[:n] / n
    return c / c[0]


def integrated_time(rho, n):
    """Sokal's automatic window: tau(M) = 1 + 2 sum_{k=1}^{M} rho(k), the smallest M >= c tau(M).

    Returns (tau in intervals, window M, resolved, error of tau from Sokal's variance formula)."""
    taus = 1 + 2 * np.cumsum(rho[1:])
    windows = np.arange(1, len(rho))
    closed = np.nonzero(windows >= WINDOW_C * taus)[0]
    if len(closed):
        m = int(closed[0])
        tau, window, closed_ok = float(taus[m]), int(windows[m]), True
    else:
        tau, window, closed_ok = float(taus.max()), int(windows[np.argmax(taus)]), False
    error = tau * math.sqrt(2 * (2 * window + 1) / n)
    resolved = closed_ok and n >= RESOLVED_SPANS * tau
    return tau, window, resolved, error


def describe(tau, resolved, error, interval, cpu_per_unit):
    """The time and CPU seconds of a tau in intervals, as text for the table."""
    if tau < 1 and resolved:
        return f"< {interval:.3g}", f"< {interval * cpu_per_unit:.3g}"
    t, c = tau * interval, tau * interval * cpu_per_unit
    if not resolved:
        return f"> {t:.3g}", f"> {c:.3g}"
    return (f"{t:.3g} +- {error * interval:.2g}",
            f"{c:.3g} +- {error * interval * cpu_per_unit:.2g}")


def read_log(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return np.array([float(r["Z"]) for r in rows[1:] if r["Z"] != ""])


def classic_start(state_json, path):
    """The end of a run (`--format json`, every double) as a classic start, at rest.

    Not a GSD frame: its single-precision positions put disks the chains left touching a few
    1e-6 inside each other in a box of side 270, and carom refuses the overlap."""
    with open(state_json) as f:
        state = json.load(f)
    particles = state["particles"]
    radii = {p["radius"] for p in particles}
    assert len(radii) == 1 and state["boundary"] == "periodic"
    lines = ["# carom: boundary=periodic rule=elastic", str(len(particles)), repr(radii.pop()),
             " ".join(repr(x) for x in state["box"])]
    lines += [f"{p['x']!r} {p['y']!r} 0 0" for p in particles]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def run_sampler(args, sampler, common, name, folder):
    """One sampler's run from the common start for about --budget CPU seconds, and its series."""
    probe = args.probe_ecmc if sampler == "ecmc" else args.probe_md
    cpu = carom(args.carom, "run", common, probe, *sampler_options(sampler), "-q", "-o",
                os.devnull)
    # A round cadence, and the run an exact multiple of it.
    interval = float(f"{args.budget * probe / cpu / args.frames:.2g}")
    length = interval * args.frames
    frames = os.path.join(folder, f"{sampler}_{name}.gsd")
    log = os.path.join(folder, f"{sampler}_{name}.csv")
    summary_path = os.path.join(folder, f"{sampler}_{name}.json")
    cpu = carom(args.carom, "run", common, repr(length), *sampler_options(sampler), "--dump",
                frames, "--every", repr(interval), "--log", log, "--log-every", repr(interval),
                "--summary", summary_path, "-q", "-o", os.devnull)
    with open(summary_path) as f:
        summary = json.load(f)
    analysis_path = os.path.join(folder, f"{sampler}_{name}.analysis.json")
    analysis_cpu = carom(args.carom, "analyze", frames, "--r-max", "2", "-o", analysis_path)
    if not args.keep:
        os.remove(frames)
    with open(analysis_path) as f:
        psi6 = json.load(f)["psi6"]["global"]
    return {"sampler": sampler, "length": length, "interval": interval, "cpu": cpu,
            "cpu_per_unit": cpu / length, "analysis_cpu": analysis_cpu,
            "wall": summary["wall_seconds"], "events": summary["events"],
            "z_summary": summary["compressibility_factor"],
            "z_error": summary["compressibility_factor_error"],
            "z_drift": summary["compressibility_factor_drift"]["sigmas"],
            "psi6_series": psi6, "Z_series": read_log(log).tolist()}


def measure(args, phi, folder):
    """Both samplers at one packing; a run already recorded in the folder is read back."""
    name = f"{phi:.2f}"
    record = os.path.join(folder, f"runs_{name}.json")
    if os.path.exists(record):
        with open(record) as f:
            runs = json.load(f)
    else:
        start = os.path.join(folder, f"start_{name}.txt")
        carom(args.carom, "init", "--n", args.n, "--phi", phi, "--boundary", "periodic", "-o",
              start)
        end = os.path.join(folder, f"equilibrated_{name}.json")
        cpu = carom(args.carom, "run", start, args.equilibrate, *sampler_options("ecmc"),
                    "--format", "json", "-q", "-o", end)
        common = os.path.join(folder, f"equilibrated_{name}.txt")
        classic_start(end, common)
        print(f"packing {name}: {args.equilibrate:g} units of event chains from the lattice, "
              f"{cpu:.0f} CPU s", flush=True)
        runs = {"equilibrate": args.equilibrate, "equilibrate_cpu": cpu,
                "runs": [run_sampler(args, s, common, name, folder) for s in SAMPLERS]}
        with open(record, "w") as f:
            json.dump(runs, f)
    results = []
    for run in runs["runs"]:
        psi6, z = np.asarray(run["psi6_series"]), np.asarray(run["Z_series"])
        entry = dict(run, phi=phi, Z_mean=float(z.mean()), psi6_mean=float(psi6.mean()),
                     psi6_first=float(psi6[0]), psi6_last=float(psi6[-1]))
        for key, series in (("psi6", psi6), ("Z", z)):
            rho = autocorrelation(series)
            tau, window, resolved, error = integrated_time(rho, len(series))
            entry[key] = {"rho": rho, "tau": tau, "window": window, "resolved": resolved,
                          "error": error, "n": len(series)}
        results.append(entry)
        print(f"packing {name}, {run['sampler']}: {run['length']:.4g} units in {run['cpu']:.0f} "
              f"CPU s ({entry['cpu_per_unit']:.4g} s a unit), {run['events']} events, Z "
              f"{entry['Z_mean']:.4f}, |psi6| {entry['psi6_first']:.3f} -> "
              f"{entry['psi6_last']:.3f}", flush=True)
    return results


def table(results):
    lines = ["| packing | sampler | run (time units) | CPU s | CPU s a unit | events | Z (blocks) "
             "| halves apart | CPU s to Z +- 0.01 | global psi6, first -> last frame "
             "| tau psi6 (units) | tau psi6 (CPU s) | tau Z (units) | tau Z (CPU s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for e in results:
        cells = []
        for key in ("psi6", "Z"):
            s = e[key]
            cells += describe(s["tau"], s["resolved"], s["error"], e["interval"],
                              e["cpu_per_unit"])
        lines.append(f"| {e['phi']:.2f} | {'ECMC' if e['sampler'] == 'ecmc' else 'EDMD'} "
                     f"| {e['length']:.4g} | {e['cpu']:.0f} | {e['cpu_per_unit']:.3g} "
                     f"| {e['events']:.3g} | {e['z_summary']:.4f} +- {e['z_error']:.4f} "
                     f"| {e['z_drift']:.1f} errors | {e['cpu'] * (e['z_error'] / 0.01) ** 2:.3g} "
                     f"| {e['psi6_first']:.3f} -> {e['psi6_last']:.3f} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(results, path, n):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    matplotlib.rcParams["svg.hashsalt"] = "carom"  # the same bytes on every run
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    colours = {"ecmc": "tab:blue", "md": "tab:red"}
    styles = ["-", "--", ":"]
    packings = sorted({e["phi"] for e in results})
    for ax, key, title in ((axes[0], "psi6", "global |psi6|"), (axes[1], "Z", "pressure (Z)")):
        for e in results:
            rho = np.asarray(e[key]["rho"])
            half = len(rho) // 2
            lag = np.arange(1, half) * e["interval"] * e["cpu_per_unit"]
            label = f"{'ECMC' if e['sampler'] == 'ecmc' else 'EDMD'}, packing {e['phi']:.2f}"
            ax.semilogx(lag, rho[1:half], styles[packings.index(e["phi"]) % 3],
                        color=colours[e["sampler"]], label=label)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("lag (CPU seconds)")
        ax.set_title(f"autocorrelation of {title}")
    axes[0].set_ylabel("normalised autocorrelation")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"Hard disks, N = {n}: event chains (ECMC) against dynamics (EDMD)")
    fig.tight_layout()
    fig.savefig(path, metadata={"Date": None})


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom")
    parser.add_argument("--n", type=int, default=65536)
    parser.add_argument("--phi", type=float, nargs="+", default=[0.70, 0.71, 0.72])
    parser.add_argument("--equilibrate", type=float, default=300.0,
                        help="time units of event chains from the lattice to the common start")
    parser.add_argument("--budget", type=float, default=120.0,
                        help="CPU seconds of each sampler's run")
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--probe-ecmc", type=float, default=5.0,
                        help="time units of the event-chain timing run")
    parser.add_argument("--probe-md", type=float, default=0.5,
                        help="time units of the dynamics timing run")
    parser.add_argument("--plot", help="draw the autocorrelation functions to this SVG file")
    parser.add_argument("--work", help="keep the runs' files in this folder (default: a "
                        "temporary one); a packing whose runs_PHI.json is there is read back")
    parser.add_argument("--keep", action="store_true", help="keep the GSD frames")
    args = parser.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.work or tmp
        os.makedirs(folder, exist_ok=True)
        for phi in args.phi:
            results += measure(args, phi, folder)
    print(table(results))
    if args.plot:
        plot(results, args.plot, args.n)


if __name__ == "__main__":
    main()
