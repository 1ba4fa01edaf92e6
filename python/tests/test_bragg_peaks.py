"""scripts/bragg_peaks.py measures positional order: S(k) / N is 1 at the Bragg peaks of a
perfect lattice, of order 1 / N in a fluid, and the peaks are the lattice's."""

import re
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR

SCRIPT = SOURCE_DIR / "scripts" / "bragg_peaks.py"


def peaks(*args):
    done = subprocess.run([sys.executable, SCRIPT, *map(str, args)], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    header = done.stdout.splitlines()[0]
    rows = [list(map(float, line.split())) for line in done.stdout.splitlines()
            if not line.startswith("#")]
    return header, rows


def frames(cli, tmp_path, name, *init):
    start, movie = tmp_path / f"{name}.txt", tmp_path / f"{name}.gsd"
    cli("init", "--n", "1024", "--boundary", "periodic", "--seed", "1", *init, "-o", start)
    cli("run", start, "1", "--sampler", "ecmc", "--dump", movie, "--every", "0.5", "-q", "-o",
        tmp_path / "end.txt")
    return movie


def test_a_lattice_is_on_its_peaks_and_a_fluid_on_none(cli, tmp_path):
    # carom init's lattice at 0.72: 36 rows of 29 sites (the last row holds 9 disks, 20 short),
    # the reciprocal lattice (29, 18), (0, 36), (-29, 18) in whole 2 pi / L. Every disk on a site
    # at t = 0: S / N is 1 at each peak (near the last frame's, which event chains have moved on).
    header, rows = peaks(frames(cli, tmp_path, "lattice", "--phi", "0.72"))
    times = [row[0] for row in rows]
    assert times == [0.0, 0.5, 1.0]  # the frames' times, not their places
    assert all(abs(s - 1.0) < 1e-4 for s in rows[0][1:]), rows[0]
    assert all(s < rows[0][1] for s in (rows[1][1], rows[2][1]))  # the chains disorder it
    assert re.search(r"b1 \(\S+, \S+\), b2 \(\S+, \S+\), b3 \(\S+, \S+\)", header), header
    _, fluid = peaks(frames(cli, tmp_path, "fluid", "--phi", "0.4", "--random"))
    assert all(row[1] < 0.02 for row in fluid), fluid


def test_every_and_from_choose_the_frames(cli, tmp_path):
    movie = frames(cli, tmp_path, "lattice", "--phi", "0.72")
    _, rows = peaks(movie, "--every", "2")
    assert [row[0] for row in rows] == [0.0, 1.0]
    _, rows = peaks(movie, "--from", "0.5")
    assert [row[0] for row in rows] == [0.5, 1.0]
    late = subprocess.run([sys.executable, SCRIPT, movie, "--from", "5"], capture_output=True,
                          text=True)
    assert late.returncode != 0 and "no frame from time 5 on (the last at 1)" in late.stderr


def test_a_file_it_cannot_read_is_named(tmp_path):
    broken = tmp_path / "broken.gsd"
    broken.write_text("not a gsd file\n")
    done = subprocess.run([sys.executable, SCRIPT, broken], capture_output=True, text=True)
    assert done.returncode != 0
    assert str(broken) in done.stderr and "GSD" in done.stderr


def perfect_lattice(path, across, rows, shaken=False):
    """A triangular lattice that fits its periodic box exactly: `rows` rows (even) of `across`
    disks of diameter 1 at spacing 1.1 along x, as a one-frame GSD file. Its peaks are at 30, 90
    and 150 degrees; `shaken` moves every disk at random along 60 degrees, across the peak at
    150, which then stands above the other two."""
    import gsd.hoomd
    import numpy as np
    spacing = 1.1
    box = [across * spacing, rows * spacing * np.sqrt(3) / 2]
    i, j = np.meshgrid(np.arange(across), np.arange(rows), indexing="ij")
    x = ((i + 0.5 * (j % 2)) * spacing).ravel()
    y = (j * spacing * np.sqrt(3) / 2).ravel()
    if shaken:
        step = 0.05 * np.random.default_rng(1).standard_normal(x.size)
        x, y = x + step * np.cos(np.pi / 3), y + step * np.sin(np.pi / 3)
    frame = gsd.hoomd.Snapshot()  # gsd 2.7 (Debian 12): Frame from 3.0 on
    frame.particles.N = x.size
    frame.particles.position = np.column_stack(
        [x - box[0] / 2, y - box[1] / 2, np.zeros(x.size)]).astype(np.float32)
    frame.configuration.box = [box[0], box[1], 0, 0, 0, 0]
    frame.configuration.dimensions = 2
    with gsd.hoomd.open(path, "wb") as trajectory:
        trajectory.append(frame)
    return x.size


@pytest.mark.parametrize("shaken", [False, True])
def test_a_lattice_that_fits_its_box_has_as_many_sites_as_disks_and_no_strain(tmp_path, shaken):
    # Shaken, the strongest peak is at 150 degrees, and the one found 60 degrees on (modulo 180)
    # at 30: 120 degrees from it, so taken the other way round (as it is, the strain would read
    # 0.5).
    movie = tmp_path / "fits.gsd"
    count = perfect_lattice(movie, 24, 28, shaken)
    header, rows = peaks(movie)
    assert f"lattice sites {count} (sites - disks +0), shear strain 0.00000" in header, header
    assert rows[0][2] > 0.999  # b1's
    if shaken:
        assert "b1 (-24, 14)" in header, header
        assert max(rows[0][3:]) < 0.99


def test_a_rectangular_box_has_its_own_grid(tmp_path):
    # Twice as tall as wide: k = 2 pi (m / Lx, n / Ly), the peaks' angles and the strain taken
    # with each side its own.
    movie = tmp_path / "tall.gsd"
    count = perfect_lattice(movie, 24, 56)
    header, rows = peaks(movie)
    assert f"lattice sites {count} (sites - disks +0), shear strain 0.00000" in header, header
    assert min(rows[0][1:]) > 0.999
