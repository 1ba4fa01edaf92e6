"""The Python API itself: numpy shapes and dtypes, copies, properties, Simulations from arrays."""

import json
import os
from pathlib import Path

import numpy as np
import pytest

import carom
from _support import assert_bitwise_equal, assert_same_run, deterministic


@pytest.fixture(params=[2, 3], ids=["disks", "spheres"])
def sim(request):
    dim = request.param
    s = carom.init(n=64 if dim == 2 else 108, phi=0.3, dim=dim, seed=61, polydispersity=0.05,
                   boundary="walls")
    s.run(2.0)
    return s


def test_package_surface():
    for name in ("Simulation", "read", "init", "resume", "InputError", "JamError",
                 "__version__"):
        assert name in carom.__all__
        assert hasattr(carom, name)
    assert issubclass(carom.InputError, ValueError)
    assert issubclass(carom.JamError, RuntimeError)
    assert isinstance(carom.__version__, str) and carom.__version__.count(".") == 2


def test_version_is_the_cli_version(cli):
    assert carom.__version__ in cli("--version")


def test_arrays_have_the_documented_shapes_and_dtypes(sim):
    n, d = sim.n, sim.dim
    for name, shape, dtype in (("positions", (n, d), np.float64),
                               ("velocities", (n, d), np.float64),
                               ("radii", (n,), np.float64),
                               ("masses", (n,), np.float64),
                               ("wall_collisions", (n,), np.uint64),
                               ("pair_collisions", (n,), np.uint64),
                               ("box", (d,), np.float64)):
        value = getattr(sim, name)
        assert isinstance(value, np.ndarray), name
        assert value.shape == shape, name
        assert value.dtype == dtype, name
        assert value.flags.c_contiguous and value.flags.writeable, name
    assert sim.pair_collisions.sum() > 0
    assert sim.wall_collisions.sum() > 0


def test_collisions_are_a_structured_array(sim):
    log = sim.run(sim.time + 1.0, collisions=True)
    assert log.dtype.names == ("time", "i", "j")
    assert log.dtype["time"] == np.float64
    assert log.dtype["i"] == np.int64 and log.dtype["j"] == np.int64
    assert log.dtype.itemsize == 24
    assert log.ndim == 1 and len(log) > 0
    empty = sim.collisions()
    assert empty.dtype == log.dtype and empty.shape == (0,)


def test_run_without_collisions_returns_none(sim):
    assert sim.run(sim.time + 0.5) is None


def test_returned_arrays_are_copies(sim):
    before = {name: getattr(sim, name).copy()
              for name in ("positions", "velocities", "radii", "masses", "wall_collisions",
                           "pair_collisions", "box")}
    for name in before:
        array = getattr(sim, name)
        array[...] = 7
        assert not np.array_equal(array, before[name]), name
        assert_bitwise_equal(getattr(sim, name), before[name], name)
    # the run goes on as if nothing had been written
    twin = carom.init(n=sim.n, phi=0.3, dim=sim.dim, seed=61, polydispersity=0.05,
                      boundary="walls")
    twin.run(2.0)
    sim.run(3.0)
    twin.run(3.0)
    assert_same_run(sim, twin)


def test_input_arrays_are_copied():
    positions = np.array([[2.0, 2.0], [5.0, 5.0], [8.0, 2.0]])
    velocities = np.array([[1.0, 0.5], [-0.3, 1.0], [0.0, -1.0]])
    box = np.array([10.0, 10.0])
    radii = np.array([0.5, 0.7, 0.6])
    masses = np.array([1.0, 2.0, 0.5])
    sim = carom.Simulation(positions, velocities, box, radii=radii, masses=masses)
    for array in (positions, velocities, box, radii, masses):
        array += 0.125
    assert_bitwise_equal(sim.positions, np.array([[2.0, 2.0], [5.0, 5.0], [8.0, 2.0]]))
    assert_bitwise_equal(sim.velocities, np.array([[1.0, 0.5], [-0.3, 1.0], [0.0, -1.0]]))
    assert_bitwise_equal(sim.box, np.array([10.0, 10.0]))
    assert_bitwise_equal(sim.radii, np.array([0.5, 0.7, 0.6]))
    assert_bitwise_equal(sim.masses, np.array([1.0, 2.0, 0.5]))


def test_properties_reflect_the_arguments():
    sim = carom.init(n=30, phi=0.2, dim=3, boundary="periodic", rule="elastic", restitution=0.7,
                     tc=2e-4, engine="reference", seed=3)
    assert (sim.n, sim.dim, sim.boundary, sim.rule, sim.restitution, sim.tc, sim.engine) == (
        30, 3, "periodic", "elastic", 0.7, 2e-4, "reference")
    assert sim.time == 0.0 and sim.events == 0
    text = repr(sim)
    assert "30 spheres" in text and "periodic" in text and "elastic" in text
    default = carom.init(n=10, phi=0.1)
    assert (default.dim, default.boundary, default.rule, default.restitution, default.tc,
            default.engine) == (2, "periodic", "elastic", 1.0, 1e-5, "fast")
    assert "10 disks" in repr(default)


def write_classic(path, positions, velocities, box, radius, radii=None, masses=None):
    lines = [str(len(positions)), repr(radius), " ".join(repr(float(b)) for b in box)]
    for k, (p, v) in enumerate(zip(positions, velocities)):
        fields = [repr(float(x)) for x in (*p, *v)]
        if radii is not None:
            fields.append(repr(float(radii[k])))
        if masses is not None:
            fields.append(repr(float(masses[k])))
        lines.append(" ".join(fields))
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("boundary", ["walls", "periodic"])
def test_simulation_from_arrays_equals_the_file(tmp_path, dim, boundary):
    start = carom.init(n=60, phi=0.3, dim=dim, seed=62, boundary=boundary, polydispersity=0.1)
    rng = np.random.default_rng(5)
    masses = rng.uniform(0.5, 2.0, start.n)
    options = dict(boundary=boundary, rule="elastic")
    sim = carom.Simulation(start.positions, start.velocities, start.box, radii=start.radii,
                           masses=masses, **options)
    path = write_classic(tmp_path / "start.txt", start.positions, start.velocities, start.box,
                         0.5, radii=start.radii, masses=masses)
    read = carom.read(path, **options)
    assert_bitwise_equal(sim.masses, masses)
    sim.run(3.0)
    read.run(3.0)
    assert sim.events > 0
    assert_same_run(sim, read)
    assert json.loads(sim.format("json"))["input"] == "(arrays)"


def test_simulation_takes_lists_and_non_contiguous_arrays():
    positions = np.array([[2.0, 2.0], [5.0, 5.0], [8.0, 2.0]])
    velocities = np.array([[1.0, 0.5], [-0.3, 1.0], [0.0, -1.0]])
    reference = carom.Simulation(positions, velocities, [10.0, 10.0])
    fortran = carom.Simulation(np.asfortranarray(positions), np.asfortranarray(velocities),
                               np.array([10.0, 99.0, 10.0])[::2])
    strided = carom.Simulation(np.hstack([positions, positions])[:, :2],
                               velocities[::-1][::-1], (10, 10))
    lists = carom.Simulation(positions.tolist(), velocities.tolist(), [10, 10], radii=[0.5] * 3,
                             masses=1)
    for other in (fortran, strided, lists):
        assert_bitwise_equal(other.positions, positions)
        assert_bitwise_equal(other.velocities, velocities)
        assert_bitwise_equal(other.box, np.array([10.0, 10.0]))
        reference_copy = carom.Simulation(positions, velocities, [10.0, 10.0])
        reference_copy.run(7.0)
        other.run(7.0)
        assert_same_run(other, reference_copy)
    assert reference.radii.tolist() == [0.5] * 3 and reference.masses.tolist() == [1.0] * 3


def test_positions_are_wrapped_in_a_periodic_box():
    sim = carom.init(n=200, phi=0.3, seed=63, boundary="periodic", rule="elastic")
    sim.run(20.0)
    assert np.all(sim.positions >= 0.0) and np.all(sim.positions < sim.box)
    assert sim.wall_collisions.sum() == 0


def test_save_and_resume_in_python(tmp_path, sim):
    sim.save(tmp_path / "run.ckpt")
    resumed = carom.resume(tmp_path / "run.ckpt")
    assert_same_run(resumed, sim)
    target = sim.time + 1.5
    for s in (sim, resumed):
        s.run(target)
    assert_same_run(resumed, sim)
    assert (resumed.rule, resumed.boundary, resumed.engine) == (sim.rule, sim.boundary, sim.engine)


def test_format_json_is_observables_plus_particles(sim):
    data = json.loads(sim.format("json"))
    particles = data.pop("particles")
    assert deterministic(data) == deterministic(sim.observables())
    assert [p["id"] for p in particles] == list(range(sim.n))
    axes = "xyz"[:sim.dim]
    positions = np.array([[p[a] for a in axes] for p in particles])
    velocities = np.array([[p["v" + a] for a in axes] for p in particles])
    assert_bitwise_equal(positions, sim.positions)
    assert_bitwise_equal(velocities, sim.velocities)
    assert [p["wall_collisions"] for p in particles] == sim.wall_collisions.tolist()
    assert [p["pair_collisions"] for p in particles] == sim.pair_collisions.tolist()
    assert data["dimension"] == sim.dim and data["n"] == sim.n and data["end_time"] == sim.time
    assert data["events"] == sim.events


def test_jam_raises_jam_error():
    # A disk exactly as wide as the box cannot move apart from the walls.
    sim = carom.Simulation([[0.5, 5.0]], [[1.0, 0.0]], [1.0, 10.0], boundary="walls")
    with pytest.raises(carom.JamError, match="jammed"):
        sim.run(1.0)
    with pytest.raises(RuntimeError):
        carom.Simulation([[0.5, 5.0]], [[1.0, 0.0]], [1.0, 10.0], boundary="walls").run(1.0)


def test_elastic_periodic_run_conserves_energy_and_momentum():
    # The physics reaches Python: a sanity check that the arrays mean what they say.
    sim = carom.init(n=300, phi=0.4, seed=64, boundary="periodic", rule="elastic")
    m = sim.masses[:, None]
    energy = 0.5 * (m * sim.velocities ** 2).sum()
    momentum = (m * sim.velocities).sum(axis=0)
    sim.run(5.0)
    assert sim.events > 1000
    assert abs(0.5 * (m * sim.velocities ** 2).sum() - energy) < 1e-9 * energy
    assert np.allclose((m * sim.velocities).sum(axis=0), momentum, atol=1e-9)
    d = sim.positions[:, None, :] - sim.positions[None, :, :]
    d -= sim.box * np.round(d / sim.box)
    distance = np.sqrt((d ** 2).sum(axis=-1)) + np.eye(sim.n) * 1e9
    assert distance.min() >= 2 * 0.5 * (1 - 1e-9)


def test_read_starts_from_a_gsd_frame(tmp_path):
    import gsd.hoomd
    sim = carom.init(n=60, phi=0.3, seed=61, boundary="periodic", rule="elastic")
    sim.run(2.0, dump=tmp_path / "m.gsd", every=1.0)
    with gsd.hoomd.open(str(tmp_path / "m.gsd"), "rb") as trajectory:
        frame = trajectory[1]
    again = carom.read(f"{tmp_path / 'm.gsd'}:1", rule="elastic")
    assert again.n == 60 and again.time == 0.0
    box = np.asarray(frame.configuration.box[:2])
    assert np.allclose(again.positions, frame.particles.position[:, :2] + box / 2, atol=1e-5)
    assert np.allclose(again.velocities, frame.particles.velocity[:, :2])
    with pytest.raises(carom.InputError, match="frames 0 to 2, not 7"):
        carom.read(f"{tmp_path / 'm.gsd'}:7")


def test_read_takes_the_box_and_rule_its_file_records(cli, cases, tmp_path):
    # carom init records them in a `# carom:` line; a plain classic file is the classic
    # assignment's (walls, swap); a periodic box without a record is elastic; asking wins.
    start = tmp_path / "gas.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    recorded = carom.read(start)
    assert (recorded.boundary, recorded.rule) == ("periodic", "elastic")
    assert carom.read(start, rule="swap").rule == "swap"
    plain = carom.read(cases / "normal.txt")
    assert (plain.boundary, plain.rule) == ("walls", "swap")
    bare = tmp_path / "bare.txt"
    bare.write_text(start.read_text().split("\n", 1)[1])
    assert carom.read(bare, boundary="periodic").rule == "elastic"
    assert carom.read(cases / "normal.txt", restitution=0.9).rule == "elastic"
    with pytest.raises(carom.InputError, match="run it with --boundary periodic"):
        carom.read(bare)
    recorded.run(1.0, dump=tmp_path / "m.gsd", every=1.0)
    frame = carom.read(tmp_path / "m.gsd")
    assert (frame.boundary, frame.rule) == ("periodic", "elastic")
    with pytest.raises(carom.InputError, match="its box is periodic"):
        carom.read(tmp_path / "m.gsd", boundary="walls")


def test_read_can_draw_velocities_as_the_cli_does(cli, tmp_path):
    # A start at rest does nothing (Z undefined: None); kT gives it `carom run --kT`'s velocities.
    rest = tmp_path / "rest.txt"
    rest.write_text("# carom: boundary=periodic rule=elastic\n4\n0.5\n6 6\n"
                    "1 1 0 0\n4 1 0 0\n1 4 0 0\n4 4 0 0\n")
    still = carom.read(rest)
    still.run(5.0)
    assert still.events == 0 and still.observables()["compressibility_factor"] is None
    sim = carom.read(rest, kT=2.0, seed=3)
    sim.run(5.0)
    assert sim.events > 0
    out = json.loads(cli("run", rest, "5", "--kT", "2", "--seed", "3", "--format", "json"))
    assert json.loads(sim.format("json"))["particles"] == out["particles"]
    assert not np.array_equal(carom.read(rest, kT=2.0, seed=4).velocities,
                              carom.read(rest, kT=2.0, seed=3).velocities)
    with pytest.raises(ValueError, match="kT must be greater than 0"):
        carom.read(rest, kT=0.0)


def test_advance_runs_for_a_duration():
    # HOOMD's habit: run(10); run(10) is 20 time units. advance(dt) is that; run(t) is absolute.
    a = carom.init(n=100, phi=0.3, seed=5, boundary="periodic")
    a.advance(1.5)
    a.advance(1.5)
    assert a.time == 3.0
    b = carom.init(n=100, phi=0.3, seed=5, boundary="periodic")
    b.run(3.0)
    assert_same_run(a, b)
    log = a.advance(0.5, collisions=True)
    assert a.time == 3.5 and len(log) > 0 and log["time"].min() >= 3.0
    with pytest.raises(ValueError, match="dt must be >= 0"):
        a.advance(-1.0)


def test_images_unwrap_the_periodic_box():
    # A dilute gas: particles cross the box, and the unwrapped displacement says how far.
    sim = carom.init(n=50, phi=0.05, seed=8, boundary="periodic")
    start = sim.unwrapped_positions
    assert sim.images.dtype == np.int32 and sim.images.shape == (50, 2)
    assert not sim.images.any()
    sim.run(40.0)
    assert sim.images.any()  # some crossed the box
    assert np.array_equal(sim.unwrapped_positions, sim.positions + sim.images * sim.box)
    travelled = np.linalg.norm(sim.unwrapped_positions - start, axis=1)
    assert travelled.max() > sim.box.max()
    walls = carom.init(n=50, phi=0.05, seed=8, boundary="walls")
    walls.run(40.0)
    assert not walls.images.any()
    assert np.array_equal(walls.unwrapped_positions, walls.positions)


def test_a_new_dump_keeps_frames_on_multiples_of_every(tmp_path):
    # Frames stay evenly spaced (the MSD needs it): a dump opened mid-run starts at the first
    # multiple of `every` from its start on, the start itself when it is one.
    import re
    for begin, first in ((1.0, "1"), (1.3, "1.5")):
        sim = carom.init(n=40, phi=0.2, seed=9, boundary="periodic")
        sim.run(begin)
        path = tmp_path / f"from-{begin}.xyz"
        sim.run(3.0, dump=path, every=0.5)
        assert re.findall(r"Time=([0-9.e+-]+)", path.read_text())[0] == first


def test_help_documents_every_public_name():
    # help(carom.Simulation) answers every question: no public function, method or property
    # without a docstring.
    import inspect
    missing = []
    for name, value in vars(carom).items():
        if name.startswith("_") or not (inspect.isfunction(value) or inspect.isclass(value)):
            continue
        if not inspect.getdoc(value):
            missing.append(name)
    for name, value in vars(carom.Simulation).items():
        if name.startswith("_"):
            continue
        target = value.fget if isinstance(value, property) else value
        if not inspect.getdoc(target):
            missing.append(f"Simulation.{name}")
    assert not missing, missing


def test_a_name_that_is_not_utf8_is_kept_and_read_back(cli, tmp_path):
    """Regression: a file whose name is not UTF-8 (caf\\xe9.txt) could not be named at all (str
    with surrogate escapes), and its name in a summary lost the run. Names go to the library as
    their bytes; JSON holds them as \\udcXX escapes, which json.load reads as os.fsdecode's str."""
    folder = os.fsencode(tmp_path) + b"/dossier\xe9"
    os.mkdir(folder)
    start, checkpoint, movie = (folder + name for name in (b"/caf\xe9.txt", b"/c.ckpt", b"/m.xyz"))
    cli("init", "--n", 20, "--phi", 0.3, "--boundary", "periodic", "-o", os.fsdecode(start))
    for path in (start, os.fsdecode(start), Path(os.fsdecode(start))):  # bytes, str, PathLike
        sim = carom.read(path)
        sim.run(1.0, summary=folder + b"/s.json", checkpoint=checkpoint, dump=movie, every=0.5)
        with open(folder + b"/s.json") as f:
            assert os.fsencode(json.load(f)["input"]) == start
    assert os.fsencode(json.loads(sim.format("json"))["input"]) == start
    resumed = carom.resume(os.fsdecode(checkpoint))
    resumed.run(2.0, summary=folder + b"/s.json")
    with open(folder + b"/s.json") as f:
        assert os.fsencode(json.load(f)["input"]) == start
    analysis = carom.analyze(movie, html=folder + b"/page\xe9.html")
    assert os.fsencode(analysis["trajectory"]) == movie
    assert os.path.exists(folder + b"/page\xe9.html")
    # Messages name such files too (pybind11 alone gave them no message at all).
    with pytest.raises(carom.InputError, match="caf\udce9-missing.txt: cannot open"):
        carom.read(folder + b"/caf\xe9-missing.txt")
