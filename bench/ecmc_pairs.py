#!/usr/bin/env python3
"""Event-chain lift rates of carom binaries and the published straight-ECMC code, in alternating pairs.

On a machine whose speed drifts within minutes, one run of each program says little: this runs
every program once per round, the order reversed each round, so that drift falls on all alike,
and prints each round's rates and then the medians. A rate is the difference of two runs of
about 1.8 x 10^8 and 5.4 x 10^8 lifts (the run lengths of ecmc_compare.py), in M lifts/s: carom's
from START (`carom run START T --sampler ecmc`, T from 10 N lifts a unit of time), the peer's from
its own start (factors 1 and 3), its binary built as ecmc_compare.py builds it.

  bench/ecmc_pairs.py --n 65536 --start start.txt --rounds 3 build/carom old/carom --peer StraightEcmc
"""
import argparse, json, math, os, re, statistics, subprocess, tempfile, time

LIFTS = (1.8e8, 5.4e8)


def carom(binary, start, t, work):
    summary = os.path.join(work, "summary.json")
    t0 = time.perf_counter()
    subprocess.run([binary, "run", start, repr(t), "--sampler", "ecmc", "--summary", summary,
                    "--quiet", "-o", os.devnull], check=True)
    return json.load(open(summary))["lifts"], time.perf_counter() - t0


def peer(binary, n, factor, work):
    side = int(round(math.sqrt(n)))
    out = os.path.join(work, "peer.h5")
    if os.path.exists(out):
        os.remove(out)
    res = subprocess.run([binary, str(side), str(n // side), "0.7", "0", str(factor), "square", out,
                          "dummy.h5"], cwd=work, capture_output=True, text=True, check=True)
    m = re.search(r"^(\d+) collisions, ([0-9.]+) seconds", res.stdout, re.M)
    return int(m.group(1)), float(m.group(2))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("carom", nargs="+", help="carom binaries")
    ap.add_argument("--n", type=int, required=True, help="disks (a square number for the peer)")
    ap.add_argument("--start", required=True, help="carom's start, N disks at packing 0.70")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--peer", help="the peer's StraightEcmc binary")
    args = ap.parse_args()
    programs = args.carom + ([args.peer] if args.peer else [])
    rates = {p: [] for p in programs}
    with tempfile.TemporaryDirectory() as work:
        for r in range(args.rounds):
            for p in programs if r % 2 == 0 else programs[::-1]:
                if p == args.peer:
                    a, b = peer(p, args.n, 1, work), peer(p, args.n, 3, work)
                else:
                    a, b = (carom(p, args.start, lifts / (10.0 * args.n), work) for lifts in LIFTS)
                rates[p].append((b[0] - a[0]) / (b[1] - a[1]) / 1e6)
            print(r, "  ".join(f"{p}={rates[p][-1]:.2f}" for p in programs), flush=True)
    for p in programs:
        print(f"{p}: median {statistics.median(rates[p]):.2f} of {' '.join(f'{x:.2f}' for x in rates[p])}")


if __name__ == "__main__":
    main()
