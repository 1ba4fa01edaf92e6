#!/usr/bin/env python3
"""Compares carom's pressure in small periodic boxes with exact-N event-chain Monte Carlo values.

Regenerates the table "Exact-N pressures in small periodic boxes" in docs/validation.md:
    /usr/bin/python3 scripts/validate_exact_n.py [--carom build/carom] [--quick]

Reference: B. Li, Y. Nishikawa, P. Hoellmer, L. Carillo, A. C. Maggs, W. Krauth, "Hard-disk
pressure computations - a historic perspective", J. Chem. Phys. 157, 234111 (2022); data file
DigitizedData/ThisWork.csv of github.com/jellyfysh/HistoricDisks, commit
8c601dccb25f2ff0d3c92a127a13ba08f324da69 (beta P (2 sigma)^2 with sigma the radius, that is
beta P d^2 with d the diameter; errors are one standard error).

Each entry: two independent replicas (different --seed), run two at a time (--jobs). A replica
is `carom init` (periodic box, diameter 1, kT = 1), an elastic run that equilibrates, then
--blocks checkpointed continuations (`carom run --resume ck T2 --equilibrate T1`), each measuring
one block of about --block-collisions pair collisions. beta P d^2 = Z N / (Lx Ly) per block; the
estimate is the mean over the blocks of both replicas and its standard error is their scatter
over sqrt(number of blocks). Prints a Markdown table, then a few diagnostic lines.
"""
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import tempfile
import time

from carom_binary import carom_binary

SQRT3 = math.sqrt(3.0)

# (N, eta, box label, aspect Lx/Ly, beta P d^2, standard error) from ThisWork.csv.
ENTRIES = [
    (72, 0.650, "square", 1.0, 6.901074, 0.000071),
    (72, 0.660, "square", 1.0, 7.383221, 0.000087),
    (72, 0.670, "square", 1.0, 7.85637, 0.00011),
    (72, 0.650, "1 : sqrt(3)/2", 2.0 / SQRT3, 6.945931, 0.000066),
    (224, 0.670, "square", 1.0, 7.979479, 0.000058),
]

REPLICAS = 2


def henderson(eta):
    """Henderson's equation of state, used only to turn collision counts into run times."""
    return (1 + eta**2 / 8) / (1 - eta) ** 2 - 0.043 * eta**4 / (1 - eta) ** 3


def collisions_per_time(n, eta):
    # Z - 1 = omega sigma sqrt(pi m / kT) / 4 with sigma = m = kT = 1; n omega / 2 pair collisions.
    omega = 4 * (henderson(eta) - 1) / math.sqrt(math.pi)
    return n * omega / 2


def carom_json(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def run_replica(carom, entry, seed, folder, eq_collisions, block_collisions, blocks):
    n, eta, _, aspect, _, _ = entry
    tag = f"n{n}-eta{eta:.3f}-a{aspect:.4f}-s{seed}"
    start = os.path.join(folder, f"start-{tag}.txt")
    ck = os.path.join(folder, f"ck-{tag}")
    subprocess.run([carom, "init", "--n", str(n), "--phi", repr(eta), "--aspect", repr(aspect),
                    "--boundary", "periodic", "--seed", str(seed), "-o", start],
                   check=True, capture_output=True)
    rate = collisions_per_time(n, eta)
    t_eq = eq_collisions / rate
    t_block = block_collisions / rate
    s = carom_json([carom, "run", start, repr(t_eq), "--rule", "elastic", "--boundary", "periodic",
                    "--checkpoint", ck, "--format", "json", "-q"])
    eq_events = s["pair_collisions"]
    values, events = [], 0
    for b in range(blocks):
        t0, t1 = t_eq + b * t_block, t_eq + (b + 1) * t_block
        s = carom_json([carom, "run", "--resume", ck, repr(t1), "--equilibrate", repr(t0),
                        "--checkpoint", ck, "--format", "json", "-q"])
        lx, ly = s["box"]
        if s["n"] != n or abs(lx / ly - aspect) > 1e-9 or abs(s["packing_fraction"] - eta) > 1e-9:
            raise RuntimeError(f"{tag}: unexpected system n={s['n']} box={s['box']} "
                               f"eta={s['packing_fraction']}")
        if s["boundary"] != "periodic" or s["rule"] != "elastic":
            raise RuntimeError(f"{tag}: not an elastic periodic run")
        values.append(s["compressibility_factor"] * n / (lx * ly))
        events += s["window_pair_collisions"]
    return {"values": values, "events": events, "eq_events": eq_events}


def mean_and_error(values):
    k = len(values)
    m = sum(values) / k
    var = sum((v - m) ** 2 for v in values) / (k - 1)
    return m, math.sqrt(var / k)


def merged_pairs(values):
    return [(values[i] + values[i + 1]) / 2 for i in range(0, len(values) - 1, 2)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--carom", default="build/carom",
                        help="carom binary (relative paths are tried from the current directory, "
                             "then from the repository root)")
    parser.add_argument("--quick", action="store_true", help="a short smoke run (seconds)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first replica")
    parser.add_argument("--jobs", type=int, default=2, help="carom processes at once")
    parser.add_argument("--blocks", type=int, help="blocks per replica (default 24; quick 4)")
    parser.add_argument("--block-collisions", type=float,
                        help="pair collisions per block (default 5e6; quick 2e5)")
    parser.add_argument("--equilibrate-collisions", type=float,
                        help="pair collisions before measuring (default 5e6; quick 2e5)")
    args = parser.parse_args()

    carom = carom_binary(args.carom)
    blocks = args.blocks or (4 if args.quick else 24)
    block_collisions = args.block_collisions or (2e5 if args.quick else 5e6)
    eq_collisions = args.equilibrate_collisions or (2e5 if args.quick else 5e6)
    if blocks < 2:
        sys.exit("--blocks must be at least 2")

    started = time.time()
    print("| N | eta | box Lx : Ly | carom beta P d^2 | published (ECMC) | difference / combined error "
          "| collisions measured |")
    print("|---|---|---|---|---|---|---|", flush=True)
    notes = []
    with tempfile.TemporaryDirectory(prefix="carom-exact-n-") as folder, \
            concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [[pool.submit(run_replica, carom, e, args.seed + r, folder, eq_collisions,
                                block_collisions, blocks) for r in range(REPLICAS)]
                   for e in ENTRIES]
        for entry, fs in zip(ENTRIES, futures):
            n, eta, label, aspect, ref, ref_err = entry
            reps = [f.result() for f in fs]
            values = [v for rep in reps for v in rep["values"]]
            m, err = mean_and_error(values)
            combined = math.hypot(err, ref_err)
            events = sum(rep["events"] for rep in reps)
            print(f"| {n} | {eta:.3f} | {label} | {m:.4f} +- {err:.4f} | {ref:.6f} +- {ref_err:.6f} "
                  f"| {(m - ref) / combined:+.1f} | {events:.3g} ({events / n:.3g} per disk) |",
                  flush=True)
            per_rep = ", ".join(f"{mean_and_error(rep['values'])[0]:.4f} +- "
                                f"{mean_and_error(rep['values'])[1]:.4f}" for rep in reps)
            pairs = [v for rep in reps for v in merged_pairs(rep["values"])]
            notes.append(f"N={n} eta={eta:.3f} {label}: replicas {per_rep}; "
                         f"error from blocks merged in pairs {mean_and_error(pairs)[1]:.4f}; "
                         f"{len(values)} blocks of {events / len(values):.3g} collisions "
                         f"({events / len(values) / n:.3g} per disk) after "
                         f"{reps[0]['eq_events']:.3g} equilibration collisions per replica")
    print()
    for line in notes:
        print(f"- {line}")
    print(f"- wall time {time.time() - started:.0f} s with {args.jobs} carom processes at once")


if __name__ == "__main__":
    main()
