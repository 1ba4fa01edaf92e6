"""Bad arguments raise ValueError saying what is wrong; broken files raise carom.InputError (a
ValueError) naming the file and line, as the command line does; a refused call changes nothing."""

import math
import re

import numpy as np
import pytest

import carom
from _support import assert_same_run

P2 = np.array([[2.0, 2.0], [5.0, 5.0], [8.0, 2.0]])
V2 = np.array([[1.0, 0.5], [-0.3, 1.0], [0.0, -1.0]])
B2 = np.array([10.0, 10.0])


def with_position(i, k, value):
    p = P2.copy()
    p[i, k] = value
    return p


def with_velocity(i, k, value):
    v = V2.copy()
    v[i, k] = value
    return v


def simulation(**changes):
    arguments = dict(positions=P2, velocities=V2, box=B2)
    arguments.update(changes)
    return lambda: carom.Simulation(**arguments)


# name: (call, a regular expression the message must match)
BAD_ARGUMENTS = {
    # carom.init
    "init-negative-n": (lambda: carom.init(n=-5, phi=0.3), r"\bn\b.*at least 1"),
    "init-zero-n": (lambda: carom.init(n=0, phi=0.3), r"\bn\b.*at least 1"),
    "init-fractional-n": (lambda: carom.init(n=10.5, phi=0.3), r"\bn\b.*whole number"),
    "init-phi-above-disk-close-packing": (lambda: carom.init(n=100, phi=0.95),
                                          r"0\.95.*close packing of disks"),
    "init-phi-above-sphere-close-packing": (
        lambda: carom.init(n=500, phi=0.75, dim=3, boundary="periodic"),
        r"0\.75.*close packing of spheres"),
    "init-phi-zero": (lambda: carom.init(n=10, phi=0.0), r"phi"),
    "init-phi-negative": (lambda: carom.init(n=10, phi=-0.1), r"phi"),
    "init-phi-nan": (lambda: carom.init(n=10, phi=math.nan), r"phi"),
    "init-phi-string": (lambda: carom.init(n=10, phi="0.3"), r"phi must be a number"),
    "init-dim-4": (lambda: carom.init(n=10, phi=0.1, dim=4), r"dim"),
    "init-dim-1": (lambda: carom.init(n=10, phi=0.1, dim=1), r"dim"),
    "init-unknown-placement": (lambda: carom.init(n=10, phi=0.1, placement="hexagonal"),
                               r"placement.*'hexagonal'"),
    "init-unknown-boundary": (lambda: carom.init(n=10, phi=0.1, boundary="torus"),
                              r"boundary.*'torus'"),
    "init-unknown-rule": (lambda: carom.init(n=10, phi=0.1, rule="sticky"), r"rule.*'sticky'"),
    "init-unknown-engine": (lambda: carom.init(n=10, phi=0.1, engine="warp"),
                            r"engine.*'warp'"),
    "init-restitution-0": (lambda: carom.init(n=10, phi=0.1, rule="elastic", restitution=0),
                           r"restitution"),
    "init-restitution-1.5": (lambda: carom.init(n=10, phi=0.1, rule="elastic", restitution=1.5),
                             r"restitution"),
    "init-restitution-nan": (
        lambda: carom.init(n=10, phi=0.1, rule="elastic", restitution=math.nan), r"restitution"),
    "init-restitution-with-swap": (lambda: carom.init(n=10, phi=0.1, rule="swap", restitution=0.8),
                                   r"restitution.*elastic"),
    "init-negative-tc": (
        lambda: carom.init(n=10, phi=0.1, rule="elastic", restitution=0.8, tc=-1e-3), r"TC"),
    "init-box-and-radius": (lambda: carom.init(n=10, phi=0.1, box=[10.0, 10.0], radius=0.5),
                            r"box.*radius"),
    "init-box-wrong-length": (lambda: carom.init(n=10, phi=0.1, box=[10.0, 10.0, 10.0]),
                              r"box"),
    "init-radius-negative": (lambda: carom.init(n=10, phi=0.1, radius=-1.0), r"radius"),
    "init-aspect-zero": (lambda: carom.init(n=10, phi=0.1, aspect=0.0), r"aspect"),
    "init-polydispersity-negative": (lambda: carom.init(n=10, phi=0.1, polydispersity=-0.1),
                                     r"polydispersity"),
    "init-kT-negative": (lambda: carom.init(n=10, phi=0.1, kT=-1.0), r"kT"),
    "init-seed-negative": (lambda: carom.init(n=10, phi=0.1, seed=-1), r"seed"),
    "init-random-jams": (lambda: carom.init(n=100, phi=0.6, placement="random"), r"jammed"),
    # carom.Simulation
    "nan-position": (simulation(positions=with_position(1, 0, math.nan)),
                     r"position of particle 1.*not a finite number"),
    "inf-position": (simulation(positions=with_position(2, 1, math.inf)),
                     r"position of particle 2.*not a finite number"),
    "nan-velocity": (simulation(velocities=with_velocity(0, 1, math.nan)),
                     r"velocity of particle 0.*not a finite number"),
    "inf-velocity": (simulation(velocities=with_velocity(1, 0, -math.inf)),
                     r"velocity of particle 1.*not a finite number"),
    "nan-box": (simulation(box=np.array([math.nan, 10.0])), r"box"),
    "nan-radius": (simulation(radii=np.array([0.5, math.nan, 0.5])), r"radius of particle 1"),
    "positions-4-columns": (simulation(positions=np.zeros((3, 4))), r"positions.*shape"),
    "positions-1d": (simulation(positions=np.zeros(6)), r"positions.*shape"),
    "positions-3d-array": (simulation(positions=np.zeros((3, 2, 1))), r"positions.*shape"),
    "positions-empty": (simulation(positions=np.zeros((0, 2)), velocities=np.zeros((0, 2))),
                        r"positions.*shape"),
    "velocities-wrong-rows": (simulation(velocities=V2[:2]), r"velocities.*shape"),
    "velocities-wrong-columns": (simulation(velocities=np.zeros((3, 3))), r"velocities.*shape"),
    "box-wrong-length": (simulation(box=np.array([10.0, 10.0, 10.0])), r"box.*shape"),
    "box-2d-array": (simulation(box=np.array([[10.0, 10.0]])), r"box.*shape"),
    "radii-wrong-length": (simulation(radii=np.array([0.5, 0.5])), r"radii.*shape"),
    "masses-wrong-length": (simulation(masses=np.ones(4)), r"masses.*shape"),
    "int-positions": (simulation(positions=P2.astype(np.int64)), r"positions.*float64.*int64"),
    "int-velocities": (simulation(velocities=V2.astype(np.int32)),
                       r"velocities.*float64.*int32"),
    "int-box": (simulation(box=np.array([10, 10])), r"box.*float64"),
    "int-radii": (simulation(radii=np.array([1, 1, 1])), r"radii.*float64"),
    "float32-positions": (simulation(positions=P2.astype(np.float32)), r"positions.*float64"),
    "object-positions": (simulation(positions=P2.astype(object)), r"positions.*float64"),
    "string-positions": (simulation(positions=[["a", "b"], [5.0, 5.0], [8.0, 2.0]]),
                         r"positions.*numbers"),
    "overlapping-particles": (simulation(positions=np.array([[2.0, 2.0], [2.6, 2.0], [8.0, 2.0]])),
                              r"particle 1 .*overlaps particle 0"),
    "particle-outside-box": (simulation(positions=with_position(2, 0, 11.0)),
                             r"particle 2 .*outside the box"),
    "particle-overlapping-a-wall": (simulation(positions=with_position(0, 1, 0.2), boundary="walls"),
                                    r"particle 0 .*overlaps the bottom wall"),
    "zero-mass": (simulation(masses=0.0), r"mass of particle 0"),
    "negative-radius": (simulation(radii=-0.5), r"radius of particle 0"),
    "periodic-box-too-small": (lambda: carom.Simulation([[1.0, 1.0]], [[1.0, 0.0]], [1.5, 1.5],
                                                        boundary="periodic"), r"periodic"),
    "simulation-unknown-rule": (simulation(rule="sticky"), r"rule.*'sticky'"),
    "simulation-unknown-boundary": (simulation(boundary="open"), r"boundary.*'open'"),
    "simulation-unknown-engine": (simulation(engine="warp"), r"engine.*'warp'"),
    "simulation-restitution-0": (simulation(rule="elastic", restitution=0.0), r"restitution"),
    "simulation-restitution-1.5": (simulation(rule="elastic", restitution=1.5), r"restitution"),
    "simulation-restitution-with-swap": (simulation(rule="swap", restitution=0.5),
                                         r"restitution.*elastic"),
    "simulation-negative-tc": (simulation(rule="elastic", restitution=0.5, tc=-1.0), r"TC"),
    "simulation-restitution-bool": (simulation(rule="elastic", restitution=True),
                                    r"restitution must be a number"),
}


@pytest.mark.parametrize("call,pattern", BAD_ARGUMENTS.values(), ids=BAD_ARGUMENTS.keys())
def test_bad_argument_raises_value_error(call, pattern):
    with pytest.raises(ValueError) as raised:
        call()
    assert type(raised.value) in (ValueError, carom.InputError)
    assert re.search(pattern, str(raised.value)), str(raised.value)


@pytest.mark.parametrize("change,pattern", [
    (dict(rule="sticky"), r"rule.*'sticky'"),
    (dict(boundary="torus"), r"boundary.*'torus'"),
    (dict(engine="warp"), r"engine.*'warp'"),
    (dict(rule="elastic", restitution=0.0), r"restitution"),
    (dict(rule="elastic", restitution=1.5), r"restitution"),
    (dict(rule="swap", restitution=0.9), r"restitution.*elastic"),
    (dict(rule="elastic", restitution=0.9, tc=-1.0), r"TC"),
    (dict(tc="small"), r"tc must be a number"),
], ids=["rule", "boundary", "engine", "restitution-0", "restitution-1.5", "restitution-swap",
        "tc", "tc-string"])
def test_read_refuses_bad_options(cases, change, pattern):
    with pytest.raises(ValueError, match=pattern):
        carom.read(cases / "normal.txt", **change)


@pytest.fixture
def running():
    sim = carom.init(n=100, phi=0.3, seed=71, rule="elastic")
    sim.run(2.0)
    return sim


BAD_RUNS = {
    "before-now": (lambda s, d: s.run(1.0), r"before"),
    "nan": (lambda s, d: s.run(math.nan), None),
    "inf": (lambda s, d: s.run(math.inf), r"finite"),
    "beyond-1e12": (lambda s, d: s.run(2e12), r"beyond"),
    "string-time": (lambda s, d: s.run("3"), r"t must be a number"),
    "dump-without-every": (lambda s, d: s.run(3.0, dump=d / "a.xyz"), r"dump= needs every="),
    "every-without-dump": (lambda s, d: s.run(3.0, every=0.5), r"every= needs dump="),
    "bad-dump-extension": (lambda s, d: s.run(3.0, dump=d / "a.txt", every=0.5),
                           r"a\.txt.*\.xyz.*\.lammpstrj"),
    "no-dump-extension": (lambda s, d: s.run(3.0, dump=d / "trajectory", every=0.5),
                          r"trajectory"),
    "zero-every": (lambda s, d: s.run(3.0, dump=d / "a.xyz", every=0.0), r"every"),
    "negative-every": (lambda s, d: s.run(3.0, dump=d / "a.xyz", every=-1.0), r"every"),
    "nan-every": (lambda s, d: s.run(3.0, dump=d / "a.xyz", every=math.nan), r"every"),
    "dump-into-missing-directory": (
        lambda s, d: s.run(3.0, dump=d / "missing" / "a.xyz", every=0.5), r"missing"),
    "unknown-format": (lambda s, d: s.format("xml"), r"format.*'xml'"),
    "measure-from-negative": (lambda s, d: s.measure_from(-1.0), r"measure_from"),
    "measure-from-nan": (lambda s, d: s.measure_from(math.nan), r"measure_from"),
}


@pytest.mark.parametrize("call,pattern", BAD_RUNS.values(), ids=BAD_RUNS.keys())
def test_bad_run_raises_value_error_and_changes_nothing(tmp_path, running, call, pattern):
    before = running.time, running.events
    with pytest.raises(ValueError) as raised:
        call(running, tmp_path)
    if pattern:
        assert re.search(pattern, str(raised.value)), str(raised.value)
    assert (running.time, running.events) == before
    assert not (tmp_path / "a.xyz").exists() and not (tmp_path / "a.txt").exists()
    assert not (tmp_path / "trajectory").exists()
    # the refused call left the run as it was: it goes on as an untouched twin does
    twin = carom.init(n=100, phi=0.3, seed=71, rule="elastic")
    twin.run(2.0)
    running.run(4.0)
    twin.run(4.0)
    assert_same_run(running, twin)


# Broken classic files: (text, line, what the message says).
BROKEN_FILES = {
    "empty": ("", None, "empty"),
    "letters-for-n": ("five\n1\n10 10\n", 1, "whole number"),
    "zero-n": ("0\n1\n10 10\n", 1, "at least 1"),
    "zero-radius": ("1\n0\n10 10\n5 5 1 1\n", 2, "radius"),
    "one-box-side": ("1\n1\n10\n5 5 1 1\n", 3, "expected 2 or 3 numbers"),
    "three-numbers": ("1\n1\n10 10\n5 5 1\n", 4, "expected 4 to 6 numbers"),
    "not-a-number": ("1\n1\n10 10\n5 5 1 x1\n", 4, "not a number"),
    "nan": ("1\n1\n10 10\n5 5 nan 1\n", 4, "not a finite number"),
    "missing-lines": ("3\n1\n10 10\n5 5 1 1\n", 4, "ends"),
    "extra-lines": ("1\n1\n10 10\n5 5 1 1\n2 2 0 0\n", 5, "unexpected data"),
    "outside": ("1\n1\n10 10\n11 5 1 1\n", 4, "outside the box"),
    "overlap": ("2\n1\n10 10\n3 3 0 0\n4.5 3 0 0\n", 5, "overlaps particle 0"),
    "sphere-overlap": ("2\n1\n10 10 10\n3 3 3 0 0 0\n3 3 4.5 0 0 0\n", 5, "overlaps particle 0"),
}


@pytest.mark.parametrize("text,line,says", BROKEN_FILES.values(), ids=BROKEN_FILES.keys())
def test_broken_file_raises_input_error_with_file_and_line(cli, tmp_path, text, line, says):
    path = tmp_path / "broken.txt"
    path.write_bytes(text.encode())
    with pytest.raises(carom.InputError) as raised:
        carom.read(path)
    message = str(raised.value)
    assert isinstance(raised.value, ValueError)
    location = f"{path}:{line}:" if line else f"{path}:"
    assert location in message
    assert says in message
    # the very message `carom run` prints
    assert cli.error("run", path, "10") == message


def test_nonexistent_file(cli, tmp_path):
    path = tmp_path / "nowhere.txt"
    with pytest.raises(carom.InputError) as raised:
        carom.read(path)
    assert str(path) in str(raised.value) and "No such file" in str(raised.value)
    assert cli.error("run", path, "10") == str(raised.value)
    with pytest.raises(carom.InputError, match="nowhere.ckpt"):
        carom.resume(tmp_path / "nowhere.ckpt")


def test_a_directory_is_not_a_file(tmp_path):
    with pytest.raises(carom.InputError, match=re.escape(str(tmp_path))):
        carom.read(tmp_path)
    with pytest.raises(carom.InputError, match=re.escape(str(tmp_path))):
        carom.resume(tmp_path)


def corruptions(good):
    """A valid checkpoint's text spoilt in several ways."""
    return {
        "truncated": good[: len(good) // 2],
        "empty": "",
        "garbage": "garbage\n",
        "not-an-object": "[1, 2, 3]\n",
        "unknown-format": good.replace('"carom_checkpoint": 5', '"carom_checkpoint": 99'),
        "dimension-4": good.replace('"dimension": 2', '"dimension": 4'),
        "particles-missing": re.sub(r'"particles"', '"particlez"', good),
        "a-classic-file": "1\n1\n10 10\n5 5 1 1\n",
    }


@pytest.mark.parametrize("kind", list(corruptions("")))
def test_corrupt_checkpoint_raises_input_error(cli, tmp_path, running, kind):
    running.save(tmp_path / "good.ckpt")
    good = (tmp_path / "good.ckpt").read_text()
    assert '"carom_checkpoint": 5' in good and '"dimension": 2' in good and '"particles"' in good
    bad = corruptions(good)[kind]
    assert bad != good
    path = tmp_path / "bad.ckpt"
    path.write_text(bad)
    with pytest.raises(carom.InputError) as raised:
        carom.resume(path)
    assert str(path) in str(raised.value)
    assert cli.error("run", "--resume", path, "10") == str(raised.value)
    carom.resume(tmp_path / "good.ckpt")  # and the good one still resumes


def test_a_checkpoint_is_not_a_classic_file(tmp_path, running):
    running.save(tmp_path / "run.ckpt")
    with pytest.raises(carom.InputError, match=re.escape(f"{tmp_path / 'run.ckpt'}:1:")):
        carom.read(tmp_path / "run.ckpt")


# Regressions: pybind11 raised TypeError for integers beyond the C++ types and for choices that
# were not strings; a run refused for its dump closed the trajectory already open.

@pytest.mark.parametrize("call", [
    lambda: carom.init(n=2 ** 64, phi=0.1),
    lambda: carom.init(n=10, phi=0.1, seed=2 ** 64),
    lambda: carom.init(n=10, phi=0.1, dim=2 ** 31),
    lambda: carom.init(n=10, phi=0.1, rule=None),
    lambda: carom.init(n=10, phi=0.1, boundary=1),
    lambda: carom.Simulation(P2, V2, B2).format(None),
], ids=["n-2**64", "seed-2**64", "dim-2**31", "rule-None", "boundary-int", "format-None"])
def test_out_of_range_and_non_string_arguments_raise_value_error(call):
    with pytest.raises(ValueError):
        call()


def test_a_refused_dump_leaves_the_open_trajectory_alone(tmp_path):
    options = dict(n=100, phi=0.3, seed=72)
    sim = carom.init(**options)
    sim.run(2.0, dump=tmp_path / "a.xyz", every=0.5)
    with pytest.raises(ValueError):
        sim.run(3.0, dump=tmp_path / "a.txt", every=0.5)
    sim.run(4.0, dump=tmp_path / "a.xyz", every=0.5)
    whole = carom.init(**options)
    whole.run(4.0, dump=tmp_path / "whole.xyz", every=0.5)
    assert (tmp_path / "a.xyz").read_bytes() == (tmp_path / "whole.xyz").read_bytes()


@pytest.mark.parametrize("options,pattern", [
    (dict(dump="frames.xyz", every=1e-100), "more than 10\\^7 frames"),
    (dict(log="series.csv", log_every=1e-100), "more than 10\\^7 rows"),
    (dict(dump="frames.xyz", every=0.0), "needs every= DT > 0"),
    (dict(checkpoint_every=10), "checkpoint_every= needs checkpoint="),
    (dict(checkpoint="a.ckpt", checkpoint_every="soon"), "checkpoint_every="),
    (dict(dump="same.csv", every=1.0, log="same.csv", log_every=1.0), "name the same file"),
    (dict(dump="frames.dcd", every=1.0), "dcd"),
])
def test_run_refuses_what_the_command_line_refuses(tmp_path, monkeypatch, options, pattern):
    # The same checks, from the library: nothing is written, the simulation is unchanged.
    monkeypatch.chdir(tmp_path)
    sim = carom.init(n=50, phi=0.3, boundary="periodic")
    with pytest.raises(ValueError, match=pattern):
        sim.run(10.0, **options)
    assert sim.time == 0.0 and list(tmp_path.iterdir()) == []


def test_save_refuses_the_start_file_it_read(cases, tmp_path):
    """Regression: sim.save over the start file carom.read read destroyed it (carom run refuses
    --checkpoint there); a resumed checkpoint may still be saved where it was read."""
    start = tmp_path / "gas.txt"
    start.write_bytes((cases / "normal.txt").read_bytes())
    sim = carom.read(start)
    (tmp_path / "sub").mkdir()
    for path in (start, tmp_path / "sub" / ".." / "gas.txt"):
        with pytest.raises(ValueError, match="name the same file"):
            sim.save(path)
    assert start.read_bytes() == (cases / "normal.txt").read_bytes()
    sim.save(tmp_path / "run.ckpt")
    carom.resume(tmp_path / "run.ckpt").save(tmp_path / "run.ckpt")


# A refusal of the library names the options as Python spells them (kT=), not as the command line
# does (--kT), which says the same of its own options.
@pytest.mark.parametrize("call,named,cli_args,cli_named", [
    (lambda path, d: carom.read(path, thermostat="rescale", thermostat_every=1.0),
     ["thermostat=", "kT="], ["--thermostat", "rescale", "--thermostat-every", "1"],
     ["--thermostat", "--kT"]),
    (lambda path, d: carom.read(path, velocity_profile=True), ["velocity_profile=", "shear="],
     ["--velocity-profile"], ["--velocity-profile", "--shear"]),
    (lambda path, d: carom.read(path).run(10.0, dump=d / "a.xyz"), ["dump=", "every="],
     None, None),
    (lambda path, d: carom.read(path).run(10.0, log_every=1.0), ["log_every=", "log="],
     ["--log-every", "1"], ["--log-every", "--log"]),
    (lambda path, d: carom.read(path).run(10.0, equilibrate=20.0), ["equilibrate=", "t="],
     ["--equilibrate", "20"], ["--equilibrate", "END_TIME"]),
], ids=["thermostat-kT", "profile-shear", "dump-every", "log-every-log", "equilibrate-end"])
def test_a_refusal_names_the_python_keywords(cli, cases, tmp_path, call, named, cli_args,
                                              cli_named):
    with pytest.raises(ValueError) as raised:
        call(cases / "normal.txt", tmp_path)
    message = str(raised.value)
    for keyword in named:
        assert keyword in message, message
    assert "--" not in message, message
    if cli_args is not None:
        cli_message = cli.error("run", cases / "normal.txt", "10", *cli_args)
        for option in cli_named:
            assert option in cli_message, cli_message


def test_an_unknown_keyword_is_a_type_error():
    with pytest.raises(TypeError, match="'colour'"):
        carom.init(n=10, phi=0.1, colour="red")
    with pytest.raises(TypeError, match="'colour'"):
        carom.Simulation(P2, V2, B2).run(1.0, colour="red")
