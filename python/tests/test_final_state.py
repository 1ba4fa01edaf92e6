"""A run's end as a start (`carom run --final`, sim.run(final=...)): the same bytes from either,
read back to the last bit by carom and by gsd.hoomd as HOOMD's schema, a jammed packing that
single precision would leave overlapping included; -o refuses a trajectory's name."""

import gsd.hoomd
import numpy as np
import pytest

import carom


@pytest.mark.parametrize("name", ["end.gsd", "end.txt"])
def test_the_end_state_is_the_same_file_from_the_cli_and_python(cli, tmp_path, name):
    start = tmp_path / "start.txt"
    cli("init", "--n", "300", "--phi", "0.5", "--polydispersity", "0.1", "--boundary", "periodic",
        "-o", start)
    cli("run", start, "4", "--final", tmp_path / f"cli-{name}", "-q", "-o", tmp_path / "out.txt")
    sim = carom.read(start)
    sim.run(4, final=tmp_path / f"py-{name}")
    assert (tmp_path / f"cli-{name}").read_bytes() == (tmp_path / f"py-{name}").read_bytes()
    back = carom.read(tmp_path / f"py-{name}")
    assert np.array_equal(back.positions, sim.positions)  # every bit
    assert np.array_equal(back.velocities, sim.velocities)
    assert np.array_equal(back.radii, sim.radii)
    assert back.boundary == "periodic"


def test_gsd_hoomd_reads_the_end_state_with_carom_s_copies_as_logged_quantities(tmp_path):
    sim = carom.init(200, 0.4, dim=3, boundary="periodic")
    sim.run(2, final=tmp_path / "end.gsd")
    with gsd.hoomd.open(tmp_path / "end.gsd") as f:
        frame = f[0]
    box = np.asarray(sim.box)
    assert np.allclose(frame.particles.position + box / 2, sim.positions, atol=1e-5)
    assert np.array_equal(frame.log["carom/position"], sim.positions)
    assert frame.log["carom/position"].dtype == np.float64


def test_a_jammed_packing_goes_on_from_its_gsd_end_without_overlaps(cli, tmp_path):
    """Single precision moves touching disks of a jammed packing into each other; the end state's
    double copies keep them touching, and the overlap check holds."""
    start, jammed = tmp_path / "gas.txt", tmp_path / "jammed.txt"
    cli("init", "--n", "200", "--phi", "0.3", "--polydispersity", "0.2", "--boundary", "periodic",
        "-o", start)
    cli("compress", start, "--jam", "--boundary", "periodic", "--unit-diameter", "-o", jammed, "-q")
    cli("run", jammed, "0", "--final", tmp_path / "jammed.gsd", "-q", "-o", tmp_path / "t.txt")
    cli("run", tmp_path / "jammed.gsd", "1", "--check", "-q", "-o", tmp_path / "t.txt")
    # The same frame without carom's copies is refused as overlapping.
    with gsd.hoomd.open(tmp_path / "jammed.gsd") as f:
        frame = f[0]
    frame.log = {}
    with gsd.hoomd.open(tmp_path / "single.gsd", "wb") as f:
        f.append(frame)
    assert "overlap" in cli.error("run", tmp_path / "single.gsd", "1", "-q")


def test_event_chains_end_at_rest(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "256", "--phi", "0.6", "--boundary", "periodic", "-o", start)
    cli("run", start, "2", "--sampler", "ecmc", "--final", tmp_path / "end.txt", "-q",
        "-o", tmp_path / "t.txt")
    back = carom.read(tmp_path / "end.txt")
    assert not back.velocities.any()
    assert "--kT" in cli.run("run", tmp_path / "end.txt", "1", "-o", "/dev/null") + cli.last_stderr


@pytest.mark.parametrize("name", ["end.gsd", "end.xyz", "end.lammpstrj", "END.XYZ"])
def test_o_refuses_a_trajectory_s_name(cli, tmp_path, name):
    start = tmp_path / "start.txt"
    cli("init", "--n", "16", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    assert "--final" in cli.error("run", start, "1", "-o", tmp_path / name)
    assert not (tmp_path / name).exists()
