#!/usr/bin/env python3
"""Other tools read carom's trajectories: ASE reads every frame of the extended XYZ and of the
LAMMPS dump, with the right box and positions. Usage: read_trajectories.py CAROM"""
import json
import os
import subprocess
import sys
import tempfile

import ase.io
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
    subprocess.run([carom, *args], check=True)


with tempfile.TemporaryDirectory() as folder:
    start = os.path.join(folder, "start.txt")
    for boundary in ("periodic", "walls"):
        carom_run("init", "--n", "60", "--phi", "0.4", "--boundary", boundary, "-o", start)
        paths = {ext: os.path.join(folder, f"traj.{ext}") for ext in ("xyz", "lammpstrj")}
        finals = []
        for path in [None, *paths.values()]:
            out = os.path.join(folder, "final.json")
            dump = ["--dump", path, "--every", "0.5"] if path else []
            carom_run("run", start, "2", "--rule", "elastic", "--boundary", boundary,
                      "--format", "json", "-o", out, *dump)
            with open(out) as f:
                finals.append(json.load(f))
        # Writing frames does not change the dynamics: the final states are bit-identical.
        check(finals[0]["particles"] == finals[1]["particles"] == finals[2]["particles"],
              f"{boundary}: final state changed by --dump")
        final = np.array([[p["x"], p["y"], 0.0] for p in finals[0]["particles"]])
        box = finals[0]["box"]

        frames = ase.io.read(paths["xyz"], index=":")
        check(len(frames) == 5, f"{boundary}: xyz has {len(frames)} frames, expected 5")
        check(np.allclose(frames[-1].cell.lengths(), [box[0], box[1], 1.0]), "xyz cell")
        check(list(frames[-1].pbc) == ([True, True, False] if boundary == "periodic"
                                       else [False, False, False]), "xyz pbc")
        check(np.allclose(frames[-1].positions, final, atol=1e-12), "xyz last frame positions")
        check(abs(frames[2].info["Time"] - 1.0) < 1e-12, "xyz frame time")
        check(np.allclose(frames[0].arrays["radius"], 0.5), "xyz radius column")

        dumped = ase.io.read(paths["lammpstrj"], index=":", format="lammps-dump-text")
        check(len(dumped) == 5, f"{boundary}: lammpstrj has {len(dumped)} frames, expected 5")
        check(np.allclose(dumped[-1].cell.lengths()[:2], box), "lammpstrj cell")
        check(np.allclose(dumped[-1].positions, final, atol=1e-9), "lammpstrj last frame positions")

    # Spheres: real z, a 3D box and three periodic axes.
    spheres = os.path.join(folder, "spheres.txt")
    with open(spheres, "w") as f:
        f.write("8\n0.5\n5 6 7\n")
        for i in range(8):
            x, y, z = 1 + 3 * (i % 2), 1.5 + 3 * (i // 2 % 2), 1.5 + 4 * (i // 4)
            f.write(f"{x} {y} {z} {0.3 - 0.1 * i} {0.05 * i - 0.2} {0.4 - 0.1 * (i % 3)}\n")
    for boundary in ("periodic", "walls"):
        paths = {ext: os.path.join(folder, f"spheres.{ext}") for ext in ("xyz", "lammpstrj")}
        out = os.path.join(folder, "spheres.json")
        for path in paths.values():
            carom_run("run", spheres, "3", "--rule", "elastic", "--boundary", boundary,
                      "--format", "json", "-o", out, "--dump", path, "--every", "1")
        with open(out) as f:
            result = json.load(f)
        final = np.array([[p["x"], p["y"], p["z"]] for p in result["particles"]])
        frames = ase.io.read(paths["xyz"], index=":")
        check(len(frames) == 4, f"3D {boundary}: xyz has {len(frames)} frames, expected 4")
        check(np.allclose(frames[-1].cell.lengths(), [5, 6, 7]), "3D xyz cell")
        check(list(frames[-1].pbc) == [boundary == "periodic"] * 3, "3D xyz pbc")
        check(np.allclose(frames[-1].positions, final, atol=1e-12), "3D xyz last frame positions")
        check(np.ptp(frames[-1].positions[:, 2]) > 1.0, "3D xyz has real z")
        dumped = ase.io.read(paths["lammpstrj"], index=":", format="lammps-dump-text")
        check(len(dumped) == 4, f"3D {boundary}: lammpstrj has {len(dumped)} frames")
        check(np.allclose(dumped[-1].cell.lengths(), [5, 6, 7]), "3D lammpstrj cell")
        check(np.allclose(dumped[-1].positions, final, atol=1e-9), "3D lammpstrj positions")

    # ASE reads velocities and masses from the xyz (the masses and momenta columns), and the image
    # flags unwrap a periodic run: no jump between frames, and the mean-square displacement from
    # the unwrapped positions equals the one from the velocities of a free flight.
    heavy = os.path.join(folder, "heavy.txt")
    with open(heavy, "w") as f:
        f.write("3\n0.5\n6 5\n")
        f.write("1 1 2.3 0.4 0.5 2.0\n3 3 -1.1 1.7 0.5 0.5\n5 1.5 0.2 -3.1 0.5 1.0\n")
    traj = os.path.join(folder, "heavy.xyz")
    out = os.path.join(folder, "heavy.json")
    carom_run("run", heavy, "20", "--rule", "elastic", "--boundary", "periodic", "--format",
              "json", "-o", out, "--dump", traj, "--every", "0.25")
    with open(out) as f:
        result = json.load(f)
    frames = ase.io.read(traj, index=":")
    velocities = np.array([[p["vx"], p["vy"], 0.0] for p in result["particles"]])
    check(np.allclose(frames[-1].get_velocities(), velocities, rtol=1e-14, atol=1e-14),
          "ASE get_velocities() from the xyz")
    check(np.allclose(frames[-1].get_masses(), [2.0, 0.5, 1.0]), "ASE get_masses() from the xyz")
    lengths = np.array([6.0, 5.0, 1.0])
    unwrapped = [fr.positions + fr.arrays["image"] * lengths for fr in frames]
    steps = np.abs(np.diff(np.array(unwrapped), axis=0))
    # At most 6.7 (all the energy in the lightest disk) x 0.25 per axis; a wrong flag jumps by a box.
    check(np.all(steps[:, :, :2] < 1.7), "image flags: no jump between frames of 0.25")
    moved = np.abs(np.array([fr.arrays["image"] for fr in frames])).max()
    check(moved >= 3, f"image flags: the disks crossed the box ({moved} times at most)")
    # Total momentum is conserved, so the mass-weighted mean unwrapped position moves uniformly.
    masses = frames[0].get_masses()[:, None]
    centre = [np.sum(masses * u, axis=0) / masses.sum() for u in unwrapped]
    momentum = np.sum(masses * velocities, axis=0) / masses.sum()
    times = np.array([fr.info["Time"] for fr in frames])
    expected = centre[0] + np.outer(times - times[0], momentum)
    check(np.allclose(np.array(centre), expected, atol=1e-9),
          "image flags: the centre of mass of the unwrapped positions moves uniformly")

    # GSD (HOOMD's schema), read by Debian's python3-gsd, frame by frame against the xyz dump of
    # the same run: 2D and 3D, periodic and walls.
    # 61 frames of 12 chunks outgrow the first index block twice.
    for name, dim_args, boundary, every in (("disks", [], "periodic", 0.1),
                                            ("disks", [], "walls", 0.5),
                                            ("spheres", ["--dim", "3"], "periodic", 0.5)):
        start = os.path.join(folder, f"gsd-{name}.txt")
        carom_run("init", *dim_args, "--n", "150", "--phi", "0.3", "--boundary", boundary,
                  "--polydispersity", "0.1", "-o", start)
        paths = {ext: os.path.join(folder, f"same.{ext}") for ext in ("xyz", "gsd")}
        for path in paths.values():
            carom_run("run", start, "6", "--rule", "elastic", "--boundary", boundary, "-o",
                      os.devnull, "--dump", path, "--every", str(every))
        xyz = ase.io.read(paths["xyz"], index=":")
        label = f"gsd {name} {boundary}"
        with gsd.hoomd.open(paths["gsd"], "rb") as trajectory:
            frames = round(6 / every) + 1
            check(len(trajectory) == len(xyz) == frames, f"{label}: {len(trajectory)} frames")
            dim = 3 if name == "spheres" else 2
            for k, (frame, other) in enumerate(zip(trajectory, xyz)):
                lengths = other.cell.lengths()
                box = np.array(frame.configuration.box)
                expected_box = [*lengths[:dim], *([0.0] if dim == 2 else []), 0, 0, 0]
                check(np.allclose(box, expected_box), f"{label}: box {box}")
                check(frame.configuration.dimensions == dim, f"{label}: dimensions")
                check(frame.configuration.step == k, f"{label}: step {frame.configuration.step}")
                check(abs(frame.log["time"][0] - other.info["Time"]) < 1e-12, f"{label}: time")
                check(frame.particles.N == len(other), f"{label}: N")
                check(list(frame.particles.types) == ["A"], f"{label}: types")
                centred = other.positions.copy()
                centred[:, :dim] -= lengths[:dim] / 2
                check(np.allclose(frame.particles.position, centred, atol=1e-5),
                      f"{label}: frame {k} positions")
                check(np.all(np.abs(frame.particles.position[:, :dim]) <= lengths[:dim] / 2),
                      f"{label}: positions in [-L/2, L/2]")
                check(np.allclose(frame.particles.velocity, other.arrays["velo"], atol=1e-6),
                      f"{label}: frame {k} velocities")
                check(np.allclose(frame.particles.diameter, 2 * other.arrays["radius"]),
                      f"{label}: diameters")
                check(np.allclose(frame.particles.mass, other.get_masses()), f"{label}: masses")
                check(np.array_equal(frame.particles.image, other.arrays["image"]),
                      f"{label}: frame {k} image flags")
            if boundary == "periodic":
                moved = max(np.abs(f.particles.image).max() for f in trajectory)
                check(moved > 0, f"{label}: some particle crossed the box")

    # A start from a GSD file that HOOMD's own library wrote (gsd.hoomd), 2D, centred positions,
    # frames 0 and 1 (frame 1 lacks the velocities and masses: frame 0's are used).
    made = os.path.join(folder, "hoomd.gsd")
    Frame = getattr(gsd.hoomd, "Frame", None) or gsd.hoomd.Snapshot  # gsd 3 renamed it
    first = Frame()
    first.configuration.box = [8.0, 6.0, 0.0, 0, 0, 0]
    first.configuration.dimensions = 2
    first.particles.N = 3
    first.particles.types = ["A"]
    first.particles.position = [[-3.0, -2.0, 0.0], [0.5, 1.0, 0.0], [2.5, -2.5, 0.0]]
    first.particles.velocity = [[0.5, 0.25, 0.0], [-1.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
    first.particles.diameter = [1.0, 1.5, 1.0]
    first.particles.mass = [1.0, 2.0, 0.5]
    first.particles.image = [[0, 0, 0], [1, -2, 0], [0, 0, 0]]
    second = Frame()
    second.configuration.box = [8.0, 6.0, 0.0, 0, 0, 0]
    second.configuration.dimensions = 2
    second.particles.N = 3
    second.particles.position = [[-2.0, -2.0, 0.0], [0.5, 2.0, 0.0], [3.5, 2.5, 0.0]]
    with gsd.hoomd.open(made, "wb") as trajectory:
        trajectory.append(first)
        trajectory.append(second)
    for spec, frame in ((made + ":0", first), (made, second)):
        out = os.path.join(folder, "from-gsd.json")
        carom_run("run", spec, "0", "--rule", "elastic", "--format", "json", "-o", out)
        with open(out) as f:
            result = json.load(f)
        check(result["boundary"] == "periodic" and result["box"] == [8.0, 6.0], f"{spec}: box")
        got = np.array([[p["x"], p["y"]] for p in result["particles"]])
        expected = np.array(frame.particles.position)[:, :2] + [4.0, 3.0]
        check(np.allclose(got, expected), f"{spec}: positions moved into [0, L)")
        check([p["vx"] for p in result["particles"]] == [0.5, -1.0, 0.0], f"{spec}: velocities")
        check([p["mass"] for p in result["particles"]] == [1.0, 2.0, 0.5], f"{spec}: masses")
        check([p["radius"] for p in result["particles"]] == [0.5, 0.75, 0.5], f"{spec}: radii")
    # carom's own dump, continued from its last frame
    carom_run("run", paths["gsd"], "1", "--rule", "elastic", "-o", os.devnull)
    # What is not a usable start: exit 2, the file named, nothing run.
    with open(paths["gsd"], "rb") as f:
        whole = f.read()
    broken = {"truncated": whole[:len(whole) // 3], "not-gsd": b"x" * 300,
              "empty": b"", "bad-magic": b"\0" + whole[1:]}
    for name, data in broken.items():
        path = os.path.join(folder, f"{name}.gsd")
        with open(path, "wb") as f:
            f.write(data)
        run = subprocess.run([carom, "run", path, "1"], capture_output=True, text=True)
        check(run.returncode == 2 and path in run.stderr, f"{name}.gsd refused: {run.stderr}")
    for spec in (made + ":2", made + ":-1", made + ":x"):
        run = subprocess.run([carom, "run", spec, "1"], capture_output=True, text=True)
        check(run.returncode == 2 and "frame" in run.stderr, f"{spec} refused: {run.stderr}")

print(f"{checks - failures} passed, {failures} failed")
sys.exit(1 if failures else 0)
