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


def read_frames(path):
    """Every frame as HOOMD's reader sees it: (step, time, box, positions, velocities, images)."""
    with gsd.hoomd.open(str(path), "rb") as trajectory:
        return [(f.configuration.step, f.log["time"].tolist(), f.configuration.box.tolist(),
                 f.particles.position.tolist(), f.particles.velocity.tolist(),
                 f.particles.image.tolist()) for f in trajectory]


def test_a_resumed_run_continues_its_gsd_file_byte_for_byte(cli, tmp_path):
    """Regression: a resumed run refused to continue a .gsd dump ("cannot continue a .gsd
    trajectory yet"), so a sweep with one could never be resumed. The command line and Python,
    resumed from a checkpoint after frames from beyond it were written (a run killed after its
    last checkpoint), cut them off and go on to the file of a run never interrupted, which
    HOOMD's reader reads frame by frame."""
    start = tmp_path / "gas.txt"
    cli("init", "--n", "200", "--phi", "0.4", "--boundary", "periodic", "-o", start)
    physics = ["--rule", "elastic", "--equilibrate", "1"]
    whole = tmp_path / "whole.gsd"
    cli("run", start, "30", "--dump", whole, "--every", "0.1", "-q", *physics)
    assert len(read_frames(whole)) == 301  # the index moved to larger blocks several times

    # The command line: saved at 7.32 (between frames), then on to 19 (frames beyond the
    # checkpoint), resumed from 7.32 again.
    movie, checkpoint = tmp_path / "movie.gsd", tmp_path / "run.ckpt"
    cli("run", start, "7.32", "--dump", movie, "--every", "0.1", "--checkpoint", checkpoint, "-q",
        *physics)
    saved = checkpoint.read_bytes()
    cli("run", "--resume", checkpoint, "19", "--dump", movie, "--every", "0.1", "-q")
    checkpoint.write_bytes(saved)
    cli("run", "--resume", checkpoint, "30", "--dump", movie, "--every", "0.1", "-q")
    assert movie.read_bytes() == whole.read_bytes()

    # Python: the same, and a resumed run that ends on a frame's time, then goes on.
    movie.unlink()
    carom.read(start, rule="elastic").run(7.32, equilibrate=1, dump=str(movie), every=0.1,
                                          checkpoint=str(checkpoint))
    carom.resume(checkpoint).run(19, dump=str(movie), every=0.1)
    checkpoint.write_bytes(saved)
    resumed = carom.resume(checkpoint)
    resumed.run(12, dump=str(movie), every=0.1, checkpoint=str(checkpoint))
    carom.resume(checkpoint).run(30, dump=str(movie), every=0.1)
    assert movie.read_bytes() == whole.read_bytes()
    assert read_frames(movie) == read_frames(whole)


def test_a_gsd_file_carom_did_not_write_is_not_continued(cli, tmp_path):
    """A resumed run continues only its own GSD files: another program's (whose chunks it would
    not extend) is refused, exit 2, and left as it was."""
    start = tmp_path / "gas.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    checkpoint = tmp_path / "run.ckpt"
    cli("run", start, "1", "--checkpoint", checkpoint, "-q")
    theirs = tmp_path / "hoomd.gsd"
    write(theirs, [snapshot(1, 10.0, step=k, positions=np.zeros((1, 3), dtype=np.float32))
                   for k in range(3)])
    before = theirs.read_bytes()
    assert "not a GSD trajectory carom wrote" in cli.error(
        "run", "--resume", checkpoint, "2", "--dump", theirs, "--every", "0.5")
    assert theirs.read_bytes() == before
