"""GSD files as HOOMD's own writer (gsd.hoomd) makes them, and as a hostile one could: chunks left
out because they equal the schema's default are read as HOOMD reads them, and frames that lean on
a large frame 0 cannot make carom ask for more memory than the machine has."""

import os

import gsd.hoomd
import numpy as np
import pytest

import carom


def write(path, frames):
    with gsd.hoomd.open(str(path), "wb") as f:
        for frame in frames:
            f.append(frame)


def snapshot(n, box, step=0, positions=None):
    s = gsd.hoomd.Snapshot()
    s.configuration.step = step
    s.configuration.dimensions = 2
    s.configuration.box = [box, box, 0, 0, 0, 0]
    s.particles.N = n
    s.particles.types = ["A"]
    if positions is not None:
        s.particles.position = positions
    return s


def test_chunks_left_at_the_schemas_default_are_its_default(cli, tmp_path):
    # One disk at the box's centre: gsd.hoomd writes no particles/position (all zeros), nor
    # velocity, diameter or mass. HOOMD reads position 0 (the centre), velocity 0, diameter 1.
    path = tmp_path / "centre.gsd"
    write(path, [snapshot(1, 10.0, positions=np.zeros((1, 3), dtype=np.float32))])
    with gsd.hoomd.open(str(path), "rb") as f:
        assert np.array_equal(f[0].particles.position, np.zeros((1, 3)))
    sim = carom.read(path)
    assert sim.n == 1 and sim.boundary == "periodic"
    assert np.array_equal(sim.positions, [[5.0, 5.0]])
    assert np.array_equal(sim.velocities, [[0.0, 0.0]])
    assert np.array_equal(sim.radii, [0.5])
    assert np.array_equal(sim.masses, [1.0])
    cli("view", path, "-o", tmp_path / "centre.html")  # trajectories read it too
    assert "5" in (tmp_path / "centre.html").read_text()


def test_frames_leaning_on_a_large_frame_zero_are_refused_before_memory_runs_out(cli, tmp_path):
    # 20,000 disks in frame 0, then 19,999 frames holding only their step: 2.5 MB on disk, about
    # 30 GB once every frame has its particles. Refused up front (exit 2, file named), where it
    # asked for the memory and died; a part of it can still be viewed.
    n = 20000
    side = 300.0
    rng = np.random.default_rng(1)
    first = snapshot(n, side, positions=rng.uniform(-side / 2, side / 2, (n, 3)).astype(np.float32))
    first.particles.position[:, 2] = 0.0
    path = tmp_path / "bomb.gsd"
    write(path, [first] + [snapshot(n, side, step=k) for k in range(1, 20000)])
    assert os.path.getsize(path) < 5e6
    memory = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    if 20000 * n * 70 < memory / 2:
        pytest.skip("this machine holds the whole file")
    message = cli.error("analyze", path)
    assert "bomb.gsd" in message and "GB in memory" in message
    message = cli.error("view", path, "-o", tmp_path / "bomb.html")
    assert "--frames A:B" in message
    with pytest.raises(carom.InputError, match="GB in memory"):
        carom.analyze(path)
    cli("view", path, "--frames", "0:3", "-o", tmp_path / "part.html")
    assert (tmp_path / "part.html").stat().st_size > 0
