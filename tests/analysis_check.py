#!/usr/bin/env python3
"""carom analyze checked against physics and against independent computations from the GSD file
(python3-gsd, numpy): Z from the contact value of g(r) against the collision virial of the same
run (2D and 3D, within 2 %), the MSD and g(r) recomputed from the file's positions and image
flags, psi6 near 1 on a triangular lattice and near 0 in the fluid. Usage: analysis_check.py CAROM"""
import json
import os
import subprocess
import sys
import tempfile

import gsd.hoomd
import numpy as np

carom = sys.argv[1]
failures = 0
checks = 0


def check(condition, what):
    global failures, checks
    checks += 1
    if not condition:
        failures += 1
        print(f"FAILED: {what}")


def carom_run(*args):
    subprocess.run([carom, *args], check=True, stdout=subprocess.DEVNULL)


def unwrapped_frames(path, equilibrate):
    """Times and unwrapped positions (position + image x box) of the frames from `equilibrate`."""
    times, positions = [], []
    with gsd.hoomd.open(path) as trajectory:
        for frame in trajectory:
            t = frame.log["time"][0]
            if t < equilibrate:
                continue
            d = frame.configuration.dimensions
            box = np.array(frame.configuration.box[:d], dtype=np.float64)
            x = frame.particles.position[:, :d].astype(np.float64)
            image = frame.particles.image[:, :d].astype(np.float64)
            times.append(t)
            positions.append(x + image * box)
    return np.array(times), np.array(positions)


def msd_by_numpy(positions):
    count = len(positions)
    return np.array([np.mean(np.sum((positions[lag:] - positions[:count - lag]) ** 2, axis=2))
                     for lag in range(count)])


def pair_histogram(path, equilibrate, bin_width, bins):
    """Pairs per bin over the frames, every pair by minimum image."""
    histogram = np.zeros(bins)
    with gsd.hoomd.open(path) as trajectory:
        for frame in trajectory:
            if frame.log["time"][0] < equilibrate:
                continue
            d = frame.configuration.dimensions
            box = np.array(frame.configuration.box[:d], dtype=np.float64)
            x = frame.particles.position[:, :d].astype(np.float64) + 0.5 * box
            i, j = np.triu_indices(len(x), 1)
            delta = x[j] - x[i]
            delta -= box * np.rint(delta / box)
            r = np.sqrt(np.sum(delta ** 2, axis=1))
            r = r[r < bin_width * bins]
            histogram += np.bincount((r / bin_width).astype(int), minlength=bins)[:bins]
    return histogram


with tempfile.TemporaryDirectory() as folder:
    def path(name):
        return os.path.join(folder, name)

    for dim, n, phi, end in ((2, 1000, 0.5, 40), (3, 1000, 0.35, 30)):
        what = f"{dim}D at packing {phi}"
        carom_run("init", "--dim", str(dim), "--n", str(n), "--phi", str(phi), "--boundary",
                  "periodic", "--seed", "3", "-o", path("start.txt"))
        carom_run("run", path("start.txt"), str(end), "--rule", "elastic", "--boundary",
                  "periodic", "--equilibrate", "10", "--dump", path("run.gsd"), "--every", "0.5",
                  "--summary", path("summary.json"), "-o", path("end.txt"))
        carom_run("analyze", path("run.gsd"), "--equilibrate", "10", "-o", path("analysis.json"))
        with open(path("summary.json")) as f:
            virial = json.load(f)["compressibility_factor"]
        with open(path("analysis.json")) as f:
            analysis = json.load(f)
        contact = analysis["rdf"]["contact"]
        check(contact is not None and abs(contact["Z"] / virial - 1) < 0.02,
              f"{what}: Z from g(d+) {contact and contact['Z']} against the virial's {virial}")

        times, positions = unwrapped_frames(path("run.gsd"), 10)
        check(np.array_equal(times, analysis["time"]), f"{what}: the frames analysed")
        expected = msd_by_numpy(positions)
        got = np.array(analysis["msd"]["msd"])
        check(len(got) == len(expected) and np.allclose(got, expected, rtol=1e-9, atol=1e-12),
              f"{what}: MSD against numpy from the GSD images (largest difference "
              f"{np.max(np.abs(got - expected)) if len(got) == len(expected) else 'n/a'})")
        check(np.allclose(analysis["msd"]["t"], times - times[0], rtol=1e-12),
              f"{what}: MSD lag times")

        rdf = analysis["rdf"]
        bins = len(rdf["r"])
        histogram = pair_histogram(path("run.gsd"), 10, rdf["bin_width"], bins)
        # g over the pair count is the normalisation, which depends on the bin alone.
        g = np.array(rdf["g"])
        shell_r = np.arange(bins + 1) * rdf["bin_width"]
        shell = np.diff(np.pi * shell_r ** 2 if dim == 2 else 4 / 3 * np.pi * shell_r ** 3)
        volume = np.prod(analysis["box"])
        ideal = len(times) * n * (n - 1) / 2 * shell / volume
        check(np.max(np.abs(g * ideal - histogram)) <= 2,
              f"{what}: g(r) against the pairs numpy counts (largest difference "
              f"{np.max(np.abs(g * ideal - histogram))} pairs)")

    # psi6: a triangular lattice at packing 0.7 (t = 0; 32 x 32 sites tile a box of aspect
    # 2 / sqrt 3 exactly) against the fluid at 0.5.
    carom_run("init", "--n", "1024", "--phi", "0.7", "--lattice", "--aspect", str(2 / 3 ** 0.5),
              "--boundary", "periodic", "-o", path("lattice.txt"))
    carom_run("run", path("lattice.txt"), "1", "--rule", "elastic", "--boundary", "periodic",
              "--dump", path("lattice.gsd"), "--every", "1", "-o", path("end.txt"))
    carom_run("analyze", path("lattice.gsd"), "-o", path("lattice.json"))
    with open(path("lattice.json")) as f:
        psi6 = json.load(f)["psi6"]
    check(psi6["global"][0] > 0.999, f"psi6 of the lattice {psi6['global'][0]}")
    # carom init's rows run along x: the lattice's bonds make 0 degrees with the x axis.
    check(abs(psi6["orientation"][0]) < 1e-6,
          f"orientation of the lattice {psi6['orientation'][0]}")
    with open(path("analysis.json")) as f:  # the 3D run: no psi6
        check(json.load(f)["psi6"] is None, "psi6 of spheres is absent")
    carom_run("init", "--n", "1000", "--phi", "0.5", "--boundary", "periodic", "-o",
              path("fluid.txt"))
    carom_run("run", path("fluid.txt"), "20", "--rule", "elastic", "--boundary", "periodic",
              "--dump", path("fluid.gsd"), "--every", "1", "-o", path("end.txt"))
    carom_run("analyze", path("fluid.gsd"), "--equilibrate", "5", "-o", path("fluid.json"))
    with open(path("fluid.json")) as f:
        psi6 = json.load(f)["psi6"]
    check(max(psi6["global"]) < 0.1, f"psi6 of the fluid at 0.5 {max(psi6['global'])}")

    # A GSD file as HOOMD writes it by default (image flags in frame 0 only, later frames take
    # frame 0's by the schema): the MSD is left out, with the reason, rather than computed from
    # stale flags.
    with gsd.hoomd.open(path("run.gsd")) as source, \
            gsd.hoomd.open(path("hoomd.gsd"), "wb") as target:
        for index, frame in enumerate(source):
            if index > 0:
                frame.particles.image = None
            target.append(frame)
    result = subprocess.run([carom, "analyze", path("hoomd.gsd"), "-o", path("hoomd.json")],
                            capture_output=True, text=True)
    with open(path("hoomd.json")) as f:
        hoomd = json.load(f)
    check(result.returncode == 0 and hoomd["msd"] is None and "image flags" in result.stderr,
          f"MSD of a GSD file with image flags in frame 0 only: {result.stderr}")

print(f"{checks - failures} of {checks} checks passed")
sys.exit(1 if failures else 0)
