"""Event-chain Monte Carlo (`--sampler ecmc`, sampler="ecmc") from every front end: the same run
gives the same files, byte for byte, from the command line and Python, in one piece or resumed
from checkpoints; every output works; what needs dynamics is refused by name."""

import json

import numpy as np
import pytest

import carom
from _support import assert_bitwise_equal
from test_run_parity import CLOCK, PIECEWISE, assert_same_files, cli_options, files, folder, outputs


@pytest.fixture(params=[2, 3], ids=["disks", "spheres"])
def start(request, cli, tmp_path):
    """A periodic start file written by `carom init` at a packing where chains lift often."""
    dim = request.param
    path = tmp_path / "start.txt"
    n, phi = (300, 0.6) if dim == 2 else (256, 0.4)
    cli("init", "--dim", str(dim), "--n", str(n), "--phi", str(phi), "--seed", "4",
        "--boundary", "periodic", "-o", path)
    return path, dim


def test_pieces_give_the_files_of_one_run_in_either_front_end(cli, tmp_path, start, monkeypatch):
    start_file, dim = start
    options = outputs(dim)
    chains = dict(sampler="ecmc", seed=7)
    flags = cli_options(options)

    whole_cli = folder(tmp_path, "whole_cli", start_file)
    cli("run", "start.txt", "6", "--equilibrate", "2", "-q", *cli_options(chains), *flags,
        cwd=whole_cli)

    pieces_cli = folder(tmp_path, "pieces_cli", start_file)
    cli("run", "start.txt", "3.5", "--equilibrate", "2", "-q", *cli_options(chains), *flags,
        cwd=pieces_cli)
    cli("run", "--resume", "run.ckpt", "6", "-q", *flags, cwd=pieces_cli)

    whole_python = folder(tmp_path, "whole_python", start_file)
    monkeypatch.chdir(whole_python)
    carom.read("start.txt", **chains).run(6, equilibrate=2, **options)

    resumed_python = folder(tmp_path, "resumed_python", start_file)
    monkeypatch.chdir(resumed_python)
    carom.read("start.txt", **chains).run(3.5, equilibrate=2, **options)
    carom.resume("run.ckpt").run(6, **options)

    one_object = folder(tmp_path, "one_object", start_file)
    monkeypatch.chdir(one_object)
    sim = carom.read("start.txt", **chains)
    sim.run(2.2, equilibrate=2, **options)
    sim.run(3.5, **options)
    sim.advance(2.5, **options)

    reference = files(whole_cli, dim)
    assert_same_files(reference, files(whole_python, dim), "one piece, Python")
    reference = files(whole_cli, dim, CLOCK + PIECEWISE)
    for name, where in [("pieces, command line", pieces_cli),
                        ("pieces, Python", resumed_python),
                        ("pieces of one Simulation", one_object)]:
        assert_same_files(reference, files(where, dim, CLOCK + PIECEWISE), name)
    summary = reference["summary.json"]
    assert summary["sampler"] == "ecmc" and summary["chain_seed"] == 7
    assert summary["lifts"] == summary["pair_collisions"] > 1000
    assert summary["temperature"] == 1.0
    # Z along each axis, and the pressure as beta P = Z N / V.
    assert len(summary["directional_compressibility_factor"]) == dim
    volume = float(np.prod(summary["box"]))
    assert summary["pressure"] == pytest.approx(
        summary["compressibility_factor"] * summary["n"] / volume, rel=1e-12)


def test_other_seeds_give_other_chains_and_the_same_seed_the_same(cli, tmp_path, start):
    start_file, dim = start
    ends = {}
    for seed in (1, 1, 2):
        out = tmp_path / f"end{len(ends)}.txt"
        cli("run", start_file, "2", "--sampler", "ecmc", "--seed", str(seed), "-q", "-o", out)
        ends[len(ends)] = out.read_bytes()
    assert ends[0] == ends[1]
    assert ends[0] != ends[2]


def test_init_and_arrays_give_the_command_lines_run(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "200", "--phi", "0.55", "--seed", "3", "--boundary", "periodic", "-o", start)
    summary = tmp_path / "cli.json"
    cli("run", start, "3", "--sampler", "ecmc", "--seed", "3", "--chain-length", "4", "-q",
        "--summary", summary, "-o", tmp_path / "end.txt")
    expected = json.loads(summary.read_text())

    by_init = carom.init(200, 0.55, seed=3, boundary="periodic", sampler="ecmc", chain_length=4)
    read = carom.read(start, sampler="ecmc", seed=3, chain_length=4)
    arrays = carom.Simulation(read.positions, read.velocities, read.box, radii=read.radii,
                              boundary="periodic", sampler="ecmc", chain_length=4, seed=3)
    for name, sim in [("init", by_init), ("read", read), ("arrays", arrays)]:
        sim.run(3)
        got = sim.observables()
        for key in ("lifts", "compressibility_factor", "directional_compressibility_factor",
                    "pressure_tensor", "chain_length", "chain_seed", "sampler"):
            assert got[key] == expected[key], f"{name}: {key}"
    assert_bitwise_equal(by_init.positions, read.positions, "positions")


@pytest.mark.parametrize("options, words", [
    (["--shear", "0.1"], "--shear needs dynamics (--sampler md)"),
    (["--thermostat", "rescale", "--kT", "1", "--thermostat-every", "1"],
     "--thermostat needs dynamics (--sampler md)"),
    (["--kT", "1"], "--kT needs dynamics (--sampler md)"),
    (["--rule", "elastic"], "--rule needs dynamics (--sampler md)"),
    (["--restitution", "0.9", "--rule", "elastic"], "--restitution needs dynamics"),
    (["--engine", "reference"], "--engine reference needs dynamics"),
    (["--transport"], "--transport needs dynamics (--sampler md)"),
    (["--chain-length", "-1"], "--chain-length must be a number above 0"),
])
def test_what_needs_dynamics_is_refused_by_name(cli, tmp_path, options, words):
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    message = cli.error("run", start, "1", "--sampler", "ecmc", *options)
    assert words in message


def test_walls_are_refused(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "-o", start)  # walls, carom init's default
    message = cli.error("run", start, "1", "--sampler", "ecmc")
    assert "--sampler ecmc needs a periodic box (--boundary periodic)" in message


def test_python_words_the_refusals_its_own_way(tmp_path):
    with pytest.raises(ValueError, match='sampler="ecmc" needs a periodic box'):
        carom.init(50, 0.3, sampler="ecmc")  # walls, carom.init's default
    with pytest.raises(ValueError, match='shear= needs dynamics'):
        carom.init(50, 0.3, boundary="periodic", sampler="ecmc", shear=0.1)
    masses = carom.init(50, 0.3, boundary="periodic")
    with pytest.raises(ValueError, match="every mass must be 1"):
        carom.Simulation(masses.positions, masses.velocities, masses.box, masses=2.0,
                         boundary="periodic", sampler="ecmc")


def test_a_seed_alone_still_needs_something_to_seed(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    assert "--seed needs --kT T" in cli.error("run", start, "1", "--seed", "3")
    cli("run", start, "1", "--seed", "3", "--sampler", "ecmc", "-q", "-o", tmp_path / "end.txt")


def test_every_output_reads_back(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "400", "--phi", "0.65", "--seed", "2", "--boundary", "periodic", "-o", start)
    frames, log = tmp_path / "frames.gsd", tmp_path / "log.csv"
    cli("run", start, "20", "--sampler", "ecmc", "--check", "--dump", frames, "--every", "2",
        "--log", log, "--log-every", "2", "-q", "-o", tmp_path / "end.txt")
    report = json.loads(cli("analyze", frames, "-o", "-"))
    assert report["frames"]["count"] == 11
    rows = log.read_text().splitlines()
    header = rows[0].split(",")
    last = dict(zip(header, rows[-1].split(",")))
    assert float(last["temperature"]) == 1.0
    # The pressure tensor in beta P, as the pressure: its trace over D is about the pressure.
    trace = (float(last["pxx"]) + float(last["pyy"])) / 2
    assert trace == pytest.approx(float(last["pressure"]), rel=0.05)


def test_a_sweep_of_chains_is_its_tasks_commands_run_alone(cli, tmp_path):
    """sampler = "ecmc" in a plan's [run]: every task runs chains seeded by its own seed (the
    swept one), and its files are those of its task.txt commands run alone."""
    import os
    import subprocess
    from pathlib import Path

    from test_sweep import CLOCK as SWEEP_CLOCK, PLAN, SHORT, TASKS, TASK_FILES, contents

    (tmp_path / "sweep").mkdir()
    plan = tmp_path / "sweep" / "plan.toml"
    plan.write_text(PLAN.format(**SHORT).replace("[run]\n", '[run]\nsampler = "ecmc"\n'))
    cli("sweep", plan, "-o", "out", "-q", cwd=tmp_path / "sweep")
    swept = contents(tmp_path / "sweep" / "out")
    alone = tmp_path / "alone"
    env = dict(os.environ, PATH=f"{Path(cli.exe).parent}{os.pathsep}{os.environ['PATH']}")
    lifts = set()
    for task in TASKS:
        (alone / "out" / task).mkdir(parents=True)
        commands = tmp_path / "sweep" / "out" / task / "task.txt"
        assert "--sampler ecmc" in commands.read_text()
        proc = subprocess.run(["bash", "-e", str(commands)], cwd=alone, env=env,
                              capture_output=True, timeout=60)
        assert proc.returncode == 0, proc.stderr.decode()
        for name in TASK_FILES:
            assert (alone / "out" / task / name).read_bytes() == swept[f"{task}/{name}"], \
                f"{task}/{name}"
        summary = json.loads((alone / "out" / task / "summary.json").read_text())
        assert {k: v for k, v in summary.items() if k not in SWEEP_CLOCK} \
            == swept[f"{task}/summary.json"], task
        assert summary["sampler"] == "ecmc"
        lifts.add(summary["lifts"])
    assert len(lifts) == len(TASKS)  # four different runs, the seeds' replicas included
