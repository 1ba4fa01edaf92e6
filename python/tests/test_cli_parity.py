"""Python against the command line, bit for bit: starts (carom.init vs `carom init`), runs
(every output format), observables (--summary) and checkpoints in both directions."""

import json

import numpy as np
import pytest

import carom
from _support import (assert_bitwise_equal, assert_same_run, assert_same_state, checkpoint_state,
                      deterministic, init_cli_args, particles_of, run_cli_args)

# carom.init's arguments: 2D and 3D, walls and periodic, mono- and polydisperse, random and
# lattice placements, explicit boxes, aspect ratios, radii and temperatures.
INIT_CASES = {
    "defaults": dict(n=50, phi=0.3),
    "2d-walls-random": dict(n=200, phi=0.3, seed=3, boundary="walls"),
    "2d-periodic-lattice": dict(n=300, phi=0.6, seed=4, boundary="periodic"),
    "2d-periodic-poly-random": dict(n=150, phi=0.35, seed=5, polydispersity=0.1,
                                    boundary="periodic"),
    "2d-walls-poly-lattice": dict(n=120, phi=0.5, seed=6, polydispersity=0.05,
                                  placement="lattice", boundary="walls"),
    "2d-lattice-low-phi-hot": dict(n=100, phi=0.2, seed=7, placement="lattice", kT=2.5),
    "2d-random-box": dict(n=100, phi=0.3, seed=8, placement="random", box=[30.0, 20.0]),
    "2d-aspect-radius": dict(n=80, phi=0.25, seed=9, aspect=2.0, radius=0.7),
    "3d-walls-random": dict(dim=3, n=200, phi=0.2, seed=10, boundary="walls"),
    "3d-periodic-fcc": dict(dim=3, n=500, phi=0.45, seed=11, boundary="periodic"),
    "3d-periodic-poly": dict(dim=3, n=256, phi=0.3, seed=12, polydispersity=0.1,
                             boundary="periodic"),
    "3d-walls-lattice-box": dict(dim=3, n=100, phi=0.15, seed=13, placement="lattice",
                                 box=[12.0, 10.0, 8.0], boundary="walls"),
}


def cli_init(cli, path, **options):
    cli("init", *init_cli_args(**options), "-o", path)
    return path


@pytest.mark.parametrize("options", INIT_CASES.values(), ids=INIT_CASES.keys())
def test_init_equals_cli_init(cli, tmp_path, options):
    sim = carom.init(**options)
    path = cli_init(cli, tmp_path / "start.txt", **options)
    read = carom.read(path, boundary=options.get("boundary", "periodic"))
    assert sim.n == read.n == options["n"]
    assert sim.dim == read.dim == options.get("dim", 2)
    assert sim.boundary == read.boundary == options.get("boundary", "periodic")
    for name in ("positions", "velocities", "radii", "masses", "box"):
        assert_bitwise_equal(getattr(sim, name), getattr(read, name), name)
    if options.get("polydispersity"):
        assert len(np.unique(sim.radii)) > 1
    else:
        assert len(np.unique(sim.radii)) == 1
    assert sim.time == 0.0 and sim.events == 0


def test_init_seeds_differ(cli, tmp_path):
    # The comparisons above are not vacuous: another seed gives other particles.
    a = carom.init(n=100, phi=0.3, seed=1)
    b = carom.read(cli_init(cli, tmp_path / "s2.txt", n=100, phi=0.3, seed=2))
    assert not np.array_equal(a.positions, b.positions)
    assert not np.array_equal(a.velocities, b.velocities)


# (init options, run options, end time): the rules, boundaries, restitution, TC, engines, spheres.
RUN_CASES = {
    "swap-walls-2d": (dict(n=100, phi=0.3, seed=2, boundary="walls"), dict(rule="swap"), 5.0),
    "elastic-periodic-2d": (dict(n=200, phi=0.5, seed=3, boundary="periodic"),
                            dict(rule="elastic", boundary="periodic"), 4.0),
    "restitution-0.8": (dict(n=150, phi=0.3, seed=4, boundary="walls"),
                        dict(rule="elastic", restitution=0.8), 5.0),
    "restitution-0.5-tc": (dict(n=150, phi=0.4, seed=5, boundary="walls"),
                           dict(rule="elastic", restitution=0.5, tc=1e-3), 5.0),
    "swap-walls-3d": (dict(dim=3, n=150, phi=0.2, seed=6, boundary="walls"), dict(rule="swap"),
                      4.0),
    "elastic-periodic-3d": (dict(dim=3, n=256, phi=0.4, seed=7, boundary="periodic"),
                            dict(rule="elastic", boundary="periodic"), 2.0),
    "inelastic-periodic-3d": (dict(dim=3, n=108, phi=0.3, seed=8, boundary="periodic"),
                              dict(rule="elastic", boundary="periodic", restitution=0.9,
                                   tc=1e-4), 3.0),
    "polydisperse-elastic": (dict(n=150, phi=0.35, seed=9, polydispersity=0.1, boundary="walls"),
                             dict(rule="elastic"), 4.0),
    "reference-engine": (dict(n=60, phi=0.3, seed=10, boundary="walls"),
                         dict(engine="reference", rule="elastic"),
                         4.0),
}


@pytest.fixture(params=RUN_CASES.values(), ids=RUN_CASES.keys())
def run_case(request, cli, tmp_path):
    init_options, run_options, end = request.param
    path = cli_init(cli, tmp_path / "start.txt", **init_options)
    return path, init_options, run_options, end


def test_run_equals_cli_run(cli, run_case):
    path, init_options, run_options, end = run_case
    sim = carom.read(path, **run_options)
    sim.run(end)
    assert sim.events > 0
    args = ("run", path, repr(end), *run_cli_args(**run_options))
    assert sim.format("csv") == cli(*args, "--format", "csv")
    assert sim.format("table") == cli(*args)
    cli_json = json.loads(cli(*args, "--format", "json"))
    py_json = json.loads(sim.format("json"))
    assert py_json["particles"] == cli_json["particles"]
    assert list(py_json) == list(cli_json)
    assert deterministic(py_json) == deterministic(cli_json)
    assert py_json["input"] == cli_json["input"] == str(path)


def test_init_then_run_equals_cli_run(cli, run_case):
    # carom.init's Simulation (no file) runs as `carom init` + `carom run` do.
    path, init_options, run_options, end = run_case
    sim = carom.init(**init_options, **{k: v for k, v in run_options.items() if k != "boundary"})
    assert sim.boundary == init_options.get("boundary", "periodic")
    sim.run(end)
    cli_json = cli("run", path, repr(end), *run_cli_args(**run_options), "--format", "json")
    assert particles_of(sim.format("json")) == particles_of(cli_json)
    assert deterministic(sim.observables()) == {
        k: v for k, v in deterministic(json.loads(cli_json)).items() if k != "particles"}


def test_observables_equal_cli_summary(cli, run_case, tmp_path):
    path, _, run_options, end = run_case
    sim = carom.read(path, **run_options)
    sim.run(end)
    summary = tmp_path / "summary.json"
    cli("run", path, repr(end), *run_cli_args(**run_options), "--summary", summary, "--format",
        "csv")
    expected = json.loads(summary.read_text())
    observed = sim.observables()
    assert list(observed) == list(expected)
    assert "particles" not in observed
    assert deterministic(observed) == deterministic(expected)
    assert observed["events"] == sim.events > 0
    assert observed["end_time"] == end
    assert observed["wall_seconds"] >= 0.0


@pytest.mark.parametrize("how", ["measure_from", "reset_measurement"])
def test_equilibrate_equals_cli(cli, tmp_path, how):
    path = cli_init(cli, tmp_path / "gas.txt", n=200, phi=0.45, seed=21, boundary="periodic")
    options = dict(rule="elastic", boundary="periodic")
    sim = carom.read(path, **options)
    if how == "measure_from":
        sim.measure_from(1.5)
    else:
        sim.run(1.5)
        sim.reset_measurement()
    sim.run(4.0)
    summary = tmp_path / "summary.json"
    cli("run", path, "4", *run_cli_args(**options), "--equilibrate", "1.5", "--summary", summary)
    expected = json.loads(summary.read_text())
    assert expected["equilibrate"] == 1.5
    assert deterministic(sim.observables()) == deterministic(expected)
    # and the window matters: measured from 0 the counts differ
    whole = carom.read(path, **options)
    whole.run(4.0)
    assert whole.observables()["window_pair_collisions"] > expected["window_pair_collisions"]
    assert whole.observables()["pair_collisions"] == expected["pair_collisions"]


CHECKPOINT_CASES = {
    "elastic-periodic-2d": (dict(n=200, phi=0.5, seed=31, boundary="periodic"),
                            dict(rule="elastic", boundary="periodic")),
    "swap-walls-2d": (dict(n=100, phi=0.3, seed=32, boundary="walls"), dict(rule="swap")),
    "inelastic-tc-walls-3d": (dict(dim=3, n=150, phi=0.25, seed=33, boundary="walls"),
                              dict(rule="elastic", restitution=0.5, tc=1e-3)),
    "elastic-periodic-3d-reference": (dict(dim=3, n=108, phi=0.3, seed=34, boundary="periodic"),
                                      dict(rule="elastic", boundary="periodic",
                                           engine="reference")),
}


@pytest.fixture(params=CHECKPOINT_CASES.values(), ids=CHECKPOINT_CASES.keys())
def checkpoint_case(request, cli, tmp_path):
    init_options, run_options = request.param
    return cli_init(cli, tmp_path / "start.txt", **init_options), run_options


def test_python_checkpoint_resumed_by_cli(cli, tmp_path, checkpoint_case):
    path, options = checkpoint_case
    sim = carom.read(path, **options)
    sim.run(1.3)
    checkpoint = tmp_path / "py.ckpt"
    sim.save(checkpoint)
    sim.run(3.0)
    assert sim.format("csv") == cli("run", "--resume", checkpoint, "3", "--format", "csv")
    cli_json = json.loads(cli("run", "--resume", checkpoint, "3", "--format", "json"))
    py_json = json.loads(sim.format("json"))
    assert py_json["particles"] == cli_json["particles"]
    assert deterministic(py_json) == deterministic(cli_json)


def test_cli_checkpoint_resumed_by_python(cli, tmp_path, checkpoint_case):
    path, options = checkpoint_case
    checkpoint = tmp_path / "cli.ckpt"
    cli("run", path, "1.3", *run_cli_args(**options), "--checkpoint", checkpoint, "--format",
        "csv")
    resumed = carom.resume(checkpoint)
    assert resumed.time == 1.3
    assert resumed.events > 0
    for key, default in (("rule", "elastic"), ("boundary", "walls"), ("restitution", 1.0),
                         ("tc", 1e-5), ("engine", "fast")):
        assert getattr(resumed, key) == options.get(key, default), key
    resumed.run(3.0)
    whole = cli("run", path, "3", *run_cli_args(**options), "--format", "json")
    assert particles_of(resumed.format("json")) == particles_of(whole)
    assert deterministic(resumed.observables()) == {
        k: v for k, v in deterministic(json.loads(whole)).items() if k != "particles"}
    assert resumed.format("csv") == cli("run", path, "3", *run_cli_args(**options),
                                        "--format", "csv")


def test_checkpoints_are_the_same_file(cli, tmp_path, checkpoint_case):
    # sim.save after a run writes the very bytes `carom run --checkpoint` writes at its end (the
    # run's measurement records included), after runs in pieces the same state (each piece
    # measured its own window), and a resumed checkpoint saves back to itself.
    path, options = checkpoint_case
    cli("run", path, "1.3", *run_cli_args(**options), "--checkpoint", tmp_path / "cli.ckpt",
        "--format", "csv")
    sim = carom.read(path, **options)
    sim.run(1.3)
    sim.save(tmp_path / "py.ckpt")
    assert (tmp_path / "py.ckpt").read_bytes() == (tmp_path / "cli.ckpt").read_bytes()
    sim = carom.read(path, **options)
    for t in (0.4, 1.0, 1.3):
        sim.run(t)
    sim.save(tmp_path / "pieces.ckpt")
    assert checkpoint_state((tmp_path / "pieces.ckpt").read_bytes()) \
        == checkpoint_state((tmp_path / "cli.ckpt").read_bytes())
    carom.resume(tmp_path / "cli.ckpt").save(tmp_path / "again.ckpt")
    assert (tmp_path / "again.ckpt").read_bytes() == (tmp_path / "cli.ckpt").read_bytes()


def test_pending_measurement_survives_a_checkpoint(cli, tmp_path):
    # measure_from ahead of the checkpoint's time: the window opens after resuming, as in the CLI.
    path = cli_init(cli, tmp_path / "gas.txt", n=150, phi=0.4, seed=41, boundary="periodic")
    options = dict(rule="elastic", boundary="periodic")
    sim = carom.read(path, **options)
    sim.measure_from(2.0)
    sim.run(1.0)
    sim.save(tmp_path / "early.ckpt")
    sim.run(3.0)
    summary = tmp_path / "summary.json"
    cli("run", "--resume", tmp_path / "early.ckpt", "3", "--summary", summary)
    resumed = carom.resume(tmp_path / "early.ckpt")
    resumed.run(3.0)
    direct = tmp_path / "direct.json"
    cli("run", path, "3", *run_cli_args(**options), "--equilibrate", "2", "--summary", direct)
    expected = deterministic(json.loads(direct.read_text()))
    assert deterministic(sim.observables()) == expected
    assert deterministic(resumed.observables()) == expected
    assert deterministic(json.loads(summary.read_text())) == expected
    assert_same_run(sim, resumed, "resumed")


@pytest.mark.parametrize("kind,rate,every,shear", [
    ("rescale", None, 0.25, None), ("andersen", 0.8, 0.25, None), ("andersen", 0.8, None, None),
    ("rescale", None, 0.25, 0.4), ("andersen", 0.8, None, -0.3)])
def test_thermostats_equal_cli_and_resume_exactly(cli, tmp_path, kind, rate, every, shear):
    # carom.read with a thermostat (and a shear) runs as `carom run --thermostat` (`--shear`),
    # and a checkpoint saved on its way (Andersen's random stream included, with resets as events
    # the next one's time, and the sliding images' offset) continues it exactly, in either front
    # end.
    path = cli_init(cli, tmp_path / "gas.txt", n=150, phi=0.35, seed=2, boundary="periodic")
    options = dict(kT=1.5, thermostat=kind)
    flags = ["--kT", "1.5", "--thermostat", kind]
    if shear is not None:
        options.update(shear=shear, velocity_profile=True)
        flags += ["--shear", str(shear), "--velocity-profile"]
    if every is not None:
        options["thermostat_every"] = every
        flags += ["--thermostat-every", str(every)]
    if rate is not None:
        options["thermostat_rate"] = rate
        flags += ["--thermostat-rate", str(rate)]
    sim = carom.read(path, rule="elastic", **options)
    sim.run(4.0)
    summary = tmp_path / "summary.json"
    cli("run", path, "4", "--rule", "elastic", *flags, "--summary", summary, "-o",
        tmp_path / "final.txt")
    expected = json.loads(summary.read_text())
    assert expected["thermostat"]["kind"] == kind
    assert (expected["shear"] is None) == (shear is None)
    assert deterministic(sim.observables()) == deterministic(expected)

    half = carom.read(path, rule="elastic", **options)
    half.run(1.6)
    half.save(tmp_path / "half.ckpt")
    cli("run", "--resume", tmp_path / "half.ckpt", "4", "--summary", summary, "-o",
        tmp_path / "resumed.txt")
    # The same, "seed" (--kT's, which the checkpoint keeps) included.
    resumed_summary = deterministic(json.loads(summary.read_text()))
    assert expected["seed"] == 1
    assert resumed_summary == deterministic(expected)
    resumed = carom.resume(tmp_path / "half.ckpt")
    resumed.run(4.0)
    assert_same_state(resumed, sim)
    assert resumed_summary == deterministic(resumed.observables())


def test_bad_thermostats_are_refused_as_on_the_command_line(tmp_path, cli):
    path = cli_init(cli, tmp_path / "gas.txt", n=50, phi=0.3, boundary="periodic")
    with pytest.raises(ValueError, match="needs kT="):
        carom.read(path, thermostat="rescale", thermostat_every=1.0)
    with pytest.raises(ValueError, match="thermostat_rate="):
        carom.read(path, kT=1.0, thermostat="andersen", thermostat_every=1.0)
    with pytest.raises(ValueError, match="thermostat"):
        carom.read(path, kT=1.0, thermostat="nose-hoover", thermostat_every=1.0)


def test_bad_shears_are_refused_as_on_the_command_line(tmp_path, cli):
    walls = cli_init(cli, tmp_path / "walls.txt", n=50, phi=0.3, boundary="walls")
    with pytest.raises(ValueError, match="periodic box"):
        carom.read(walls, rule="elastic", shear=1.0)
    path = cli_init(cli, tmp_path / "gas.txt", n=50, phi=0.3, boundary="periodic")
    with pytest.raises(ValueError, match="needs shear="):
        carom.read(path, velocity_profile=True)
    with pytest.raises(ValueError, match='rule="elastic"'):
        carom.read(path, rule="swap", shear=1.0)
    with pytest.raises(ValueError, match="shear"):
        carom.init(50, 0.3, boundary="periodic", rule="elastic", shear=float("inf"))
