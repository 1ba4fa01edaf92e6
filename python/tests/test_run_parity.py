"""One run description through the command line and through Python gives the same files, byte
for byte: the trajectory, the time series, the event log, the checkpoint and the summary, whether
the run goes in one piece, in pieces continued from a checkpoint (`carom run --resume`,
carom.resume), in pieces of one Python Simulation, or is stopped by Ctrl-C and resumed. Both
front ends hand the same RunSpec to the library's Runner; this checks that they say the same."""

import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import warnings

import pytest

import carom
from _support import checkpoint_state

# The outputs, as carom.Simulation.run's keywords; the command line's options are their names.
OUTPUTS = dict(log="series.csv", log_every=0.25, events="events.csv", checkpoint="run.ckpt",
               checkpoint_every=1500, summary="summary.json")
DUMPS = {2: "frames.xyz", 3: "frames.lammpstrj"}  # the continued trajectory formats
EVERY = 0.5
FILES = ("series.csv", "events.csv", "run.ckpt", "summary.json")
# Fields of the summary that depend on the wall clock, or (the transport coefficients, whose
# blocks are spaced by the run's end in windows as short as these tests') on where a run was cut. Z's drift verdict and errors are not
# among them: their blocks double as the window grows, whatever its end.
CLOCK = ("wall_seconds", "events_per_second")
PIECEWISE = ("transport",)


def outputs(dim):
    return dict(OUTPUTS, dump=DUMPS[dim], every=EVERY)


def cli_options(options):
    args = []
    for key, value in options.items():
        args += ["--" + key.replace("_", "-"), str(value)]
    return args


def files(folder, dim, drop=CLOCK):
    """Every output file's bytes; the summary as a dict without the fields in `drop`, and the
    checkpoint without its measurement records when those are dropped (PIECEWISE)."""
    found = {}
    for name in FILES + (DUMPS[dim],):
        data = (folder / name).read_bytes()
        if name == "summary.json":
            data = {k: v for k, v in json.loads(data).items() if k not in drop}
        if name == "run.ckpt" and set(PIECEWISE) <= set(drop):
            data = checkpoint_state(data)
        found[name] = data
    return found


def assert_same_files(a, b, what):
    assert a.keys() == b.keys()
    for name in a:
        assert a[name] == b[name], f"{what}: {name} differs"


@pytest.fixture(params=[2, 3], ids=["disks", "spheres"])
def start(request, cli, tmp_path):
    """A periodic start file written by `carom init`, and its dimension."""
    dim = request.param
    path = tmp_path / "start.txt"
    n = 300 if dim == 2 else 256
    cli("init", "--dim", str(dim), "--n", str(n), "--phi", "0.45", "--seed", "4",
        "--boundary", "periodic", "-o", path)
    return path, dim


def folder(tmp_path, name, start_file):
    """A folder of its own for one way of running, holding a copy of the start file: every run
    names its files alike (relative paths), so their contents can be compared whole."""
    made = tmp_path / name
    made.mkdir()
    (made / "start.txt").write_bytes(start_file.read_bytes())
    return made


# Dynamics, and event chains (`--sampler ecmc`): the same outputs, resumed the same way.
SAMPLERS = {"dynamics": {}, "chains": {"sampler": "ecmc", "seed": 7}}


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_pieces_give_the_files_of_one_run_in_either_front_end(cli, tmp_path, start, sampler,
                                                              monkeypatch):
    start_file, dim = start
    options = outputs(dim)
    flags = cli_options(options)
    chosen = SAMPLERS[sampler]
    how = cli_options(chosen)

    whole_cli = folder(tmp_path, "whole_cli", start_file)
    cli("run", "start.txt", "6", "--equilibrate", "2", "-q", *how, *flags, cwd=whole_cli)

    pieces_cli = folder(tmp_path, "pieces_cli", start_file)
    cli("run", "start.txt", "3.5", "--equilibrate", "2", "-q", *how, *flags, cwd=pieces_cli)
    cli("run", "--resume", "run.ckpt", "6", "-q", *flags, cwd=pieces_cli)

    whole_python = folder(tmp_path, "whole_python", start_file)
    monkeypatch.chdir(whole_python)
    carom.read("start.txt", **chosen).run(6, equilibrate=2, **options)

    resumed_python = folder(tmp_path, "resumed_python", start_file)
    monkeypatch.chdir(resumed_python)
    carom.read("start.txt", **chosen).run(3.5, equilibrate=2, **options)
    carom.resume("run.ckpt").run(6, **options)

    one_object = folder(tmp_path, "one_object", start_file)
    monkeypatch.chdir(one_object)
    sim = carom.read("start.txt", **chosen)
    sim.run(2.2, equilibrate=2, **options)
    sim.run(3.5, **options)      # the same files, kept open
    sim.advance(2.5, **options)  # to 6

    reference = files(whole_cli, dim)
    assert_same_files(reference, files(whole_python, dim), "one piece, Python")
    reference = files(whole_cli, dim, CLOCK + PIECEWISE)
    for name, where in [("pieces, command line", pieces_cli),
                        ("pieces, Python", resumed_python),
                        ("pieces of one Simulation", one_object)]:
        assert_same_files(reference, files(where, dim, CLOCK + PIECEWISE), name)
    # The comparisons are not vacuous: the files hold the whole run.
    summary = reference["summary.json"]
    assert summary["end_time"] == 6.0 and summary["window_pair_collisions"] > 0
    assert summary["compressibility_factor_drift"]["intervals"] == 32  # blocks of 1/8 from t = 2
    assert summary["compressibility_factor_error"] > 0
    assert summary["sampler"] == chosen.get("sampler", "md")
    frames = reference[DUMPS[dim]].decode()
    assert frames.count("Time=" if dim == 2 else "ITEM: TIMESTEP") == 13  # t = 0, 0.5, ..., 6


INTERRUPTED = textwrap.dedent("""
    import json, os, signal, sys, threading
    import carom

    options = json.loads(sys.argv[1])
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    sim = carom.read("start.txt")
    try:
        sim.run(1e4, equilibrate=1, **options)
    except KeyboardInterrupt:
        pass
    print(sim.time)
""")

RESUMED = textwrap.dedent("""
    import json, sys
    import carom

    carom.resume("run.ckpt").run(float(sys.argv[2]), **json.loads(sys.argv[1]))
""")


def test_a_stopped_run_resumed_gives_the_files_of_one_run(cli, tmp_path, start):
    """Ctrl-C (SIGINT) stops a run at a whole instant and saves its checkpoint; resumed, in
    either front end, it gives the files of a run never stopped, which the other front end
    makes."""
    start_file, dim = start
    options = dict(outputs(dim), every=5.0, log_every=2.0, checkpoint_every=20000)
    # The command line, stopped: run again to just past where it stopped, from its checkpoint.
    stopped_cli = folder(tmp_path, "stopped_cli", start_file)
    child = subprocess.Popen([cli.exe, "run", "start.txt", "1e4", "--equilibrate", "1", "-q",
                              *cli_options(options)], cwd=stopped_cli, stderr=subprocess.PIPE,
                             text=True)
    try:
        child.wait(timeout=0.3)
    except subprocess.TimeoutExpired:
        child.send_signal(signal.SIGINT)
    stderr = child.communicate(timeout=60)[1]
    assert child.returncode == 128 + signal.SIGINT, stderr
    stopped_at = carom.resume(stopped_cli / "run.ckpt").time
    end_cli = math.ceil(stopped_at) + 1.5
    cli("run", "--resume", "run.ckpt", repr(end_cli), "-q", *cli_options(options),
        cwd=stopped_cli)

    # Python, stopped by KeyboardInterrupt, resumed by carom.resume.
    stopped_python = folder(tmp_path, "stopped_python", start_file)
    env = dict(os.environ)
    child = subprocess.run([sys.executable, "-c", INTERRUPTED, json.dumps(options)],
                           cwd=stopped_python, capture_output=True, text=True, timeout=60,
                           env=env)
    assert child.returncode == 0, child.stderr
    end_python = math.ceil(float(child.stdout)) + 1.5
    child = subprocess.run([sys.executable, "-c", RESUMED, json.dumps(options), repr(end_python)],
                           cwd=stopped_python, capture_output=True, text=True, timeout=120,
                           env=env)
    assert child.returncode == 0, child.stderr

    # Each against a run never stopped, by the other front end.
    whole_python = folder(tmp_path, "whole_python", start_file)
    child = subprocess.run([sys.executable, "-c", textwrap.dedent("""
        import json, sys
        import carom
        carom.read("start.txt").run(float(sys.argv[2]), equilibrate=1, **json.loads(sys.argv[1]))
    """), json.dumps(options), repr(end_cli)], cwd=whole_python, capture_output=True, text=True,
                           timeout=120, env=env)
    assert child.returncode == 0, child.stderr
    whole_cli = folder(tmp_path, "whole_cli", start_file)
    cli("run", "start.txt", repr(end_python), "--equilibrate", "1", "-q", *cli_options(options),
        cwd=whole_cli)

    drop = CLOCK + PIECEWISE
    assert_same_files(files(whole_python, dim, drop), files(stopped_cli, dim, drop),
                      "command line stopped and resumed")
    assert_same_files(files(whole_cli, dim, drop), files(stopped_python, dim, drop),
                      "Python stopped and resumed")


def test_transport_continued_to_a_later_end_is_the_run_in_one(cli, tmp_path):
    """The transport coefficients of windows ten blocks of their lag long or more (blocks of
    about 20 time units for spheres at 0.3) do not depend on the end: one Python Simulation run
    to 210 and then to 230, and the command line stopped at 210 and resumed to 230, report those
    of one run to 230."""
    start = tmp_path / "spheres.txt"
    cli("init", "--dim", "3", "--n", "200", "--phi", "0.3", "--boundary", "periodic",
        "-o", start)
    whole = carom.read(str(start))
    whole.run(230.0, transport=True)
    one = whole.observables()["transport"]
    assert one["blocks"] == 11
    pieces = carom.read(str(start))
    pieces.run(210.0, transport=True)
    pieces.run(230.0, transport=True)
    assert pieces.observables()["transport"] == one
    checkpoint, summary = tmp_path / "run.ckpt", tmp_path / "summary.json"
    cli("run", start, "210", "--transport", "--checkpoint", checkpoint, "-q", "-o",
        tmp_path / "first.txt")
    cli("run", "--resume", checkpoint, "230", "--transport", "--summary", summary, "-q", "-o",
        tmp_path / "second.txt")
    assert json.loads(summary.read_text())["transport"] == one


def unsettled_warnings(caught):
    return [str(w.message) for w in caught if issubclass(w.category, carom.UnsettledWarning)]


def test_a_run_warns_of_unsettled_z_as_the_command_line_does(cli, tmp_path):
    """A cooling granular gas drifts, and 1024 disks by chains at 0.71 (the coexistence region)
    have correlated blocks: sim.run warns of each with carom.UnsettledWarning in the words the
    command line prints after "carom: warning: ", once a window (a run that extends it says
    nothing more, one that opens another says it again); a steady gas warns of nothing. The
    warning names the caller's line, of run() and of advance() alike."""
    cli("init", "--n", "500", "--phi", "0.3", "--boundary", "periodic", "-o", "gas.txt",
        cwd=tmp_path)
    cli("init", "--n", "1024", "--phi", "0.71", "--boundary", "periodic", "-o", "dense.txt",
        cwd=tmp_path)
    cases = [("gas.txt", 30, dict(restitution=0.5), {}, "Z drifted from"),
             ("dense.txt", 600, dict(sampler="ecmc"), dict(equilibrate=500),
              "Z's blocks of the measurement window are correlated")]

    def caught_running(how, *args, **options):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            how(*args, **options)
        unsettled = [w for w in caught if issubclass(w.category, carom.UnsettledWarning)]
        assert all(w.filename == __file__ for w in unsettled)
        return [str(w.message) for w in unsettled]

    for start, t, settings, options, words in cases:
        cli("run", start, str(t), "--format", "json", "-o", "out.json",
            *cli_options({**settings, **options}), cwd=tmp_path)
        printed = [line[len("carom: warning: "):] for line in cli.last_stderr.splitlines()
                   if line.startswith("carom: warning: ")]
        assert len(printed) == 1 and printed[0].startswith(words), cli.last_stderr
        sim = carom.read(tmp_path / start, **settings)
        assert caught_running(sim.run, t, **options) == printed
        assert caught_running(sim.advance, 0.0) == []  # the same window: said once
        again = carom.read(tmp_path / start, **settings)
        if "equilibrate" in options:
            again.run(options["equilibrate"])
            again.measure_from(options["equilibrate"])
        assert caught_running(again.advance, t - again.time) == printed
    steady = carom.read(tmp_path / "gas.txt")
    with warnings.catch_warnings():
        warnings.simplefilter("error", carom.UnsettledWarning)
        steady.run(60, equilibrate=10)
