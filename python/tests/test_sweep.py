"""carom sweep run three ways (`carom sweep` on this machine's cores, under mpirun, and
carom.sweep on Dask) writes the same folder: results.csv and summary.csv byte for byte, and each
task's files those of its task.txt commands run alone. A sweep killed or stopped and run again,
or a Dask worker killed mid-task, changes nothing; bad plans are refused naming the line; a task
that cannot run is recorded as failed while the others are done.

Every sweep whose files are compared writes to the same absolute folder (then moved aside), since
a task's commands, summary and checkpoint name its files' paths."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import carom

distributed = pytest.importorskip("distributed")


def column_names(table):
    """A results table's columns: a pandas DataFrame's, or a numpy structured array's."""
    return list(table.dtype.names) if isinstance(table, np.ndarray) else list(table.columns)

PLAN = """\
[start]
n = 64
boundary = "periodic"

[run]
end_time = {end_time}
equilibrate = {equilibrate}
checkpoint_every = {checkpoint_every}

[sweep]
phi = [0.3, 0.5]
seed = [1, 2]
"""
# A fraction of a second for all four tasks, a checkpoint every 500 events.
SHORT = dict(end_time=20, equilibrate=5, checkpoint_every=500)
# About a second a task, so that a kill lands mid-run.
LONG = dict(end_time=6000, equilibrate=100, checkpoint_every=20000)
TASKS = ("phi=0.3,seed=1", "phi=0.3,seed=2", "phi=0.5,seed=1", "phi=0.5,seed=2")
TASK_FILES = ("start.txt", "log.csv", "checkpoint.ckpt")
CLOCK = ("wall_seconds", "events_per_second")


def write_plan(folder, text=None, **values):
    path = Path(folder) / "plan.toml"
    path.write_text(PLAN.format(**values) if text is None else text)
    return path


def contents(out):
    """What must not depend on how a sweep's tasks ran: the tables, and each task's files and its
    summary without the clock (the verdict on Z's drift included: a task resumed from a
    checkpoint goes on with the intervals it holds)."""
    files = {name: (out / name).read_bytes() for name in ("results.csv", "summary.csv")}
    left_out = CLOCK
    for task in TASKS:
        for name in TASK_FILES + ("task.txt",):
            files[f"{task}/{name}"] = (out / task / name).read_bytes()
        summary = json.loads((out / task / "summary.json").read_text())
        files[f"{task}/summary.json"] = {k: v for k, v in summary.items() if k not in left_out}
    return files


def assert_same_contents(a, b, what):
    assert list(a) == list(b), what
    for name in a:
        assert a[name] == b[name], f"{what}: {name} differs"


def set_aside(out, name):
    """Moves a finished sweep's folder away, so that the next writes to the same path."""
    return out.rename(out.with_name(name))


def sweep_process(cli, plan, out):
    return subprocess.Popen([cli.exe, "sweep", str(plan), "-o", str(out), "-q"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


def has_mpi(cli):
    """Whether there is an mpirun and carom was built with MPI."""
    return shutil.which("mpirun") is not None and "sweep: MPI" in cli("--version")


def mpi_sweep(cli, *args, cwd=None):
    """`mpirun -n 3 carom sweep ARGS` run to its end, or None without mpirun or MPI."""
    if not has_mpi(cli):
        return None
    # OpenMPI refuses to run as root unless told it may.
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return subprocess.run([shutil.which("mpirun"), "-n", "3", "--oversubscribe", cli.exe, "sweep",
                           *[str(a) for a in args]], cwd=cwd, capture_output=True, env=env,
                          timeout=120)


def wait_until(condition, process=None, seconds=60):
    """Polls until condition() holds; fails if the process ends first."""
    deadline = time.monotonic() + seconds
    while not condition():
        assert process is None or process.poll() is None, "the sweep ended before it was caught"
        assert time.monotonic() < deadline, "waited too long"
        time.sleep(0.002)


def running(out):
    """Tasks with a checkpoint and no summary: caught mid-run."""
    return [t for t in TASKS if (out / t / "checkpoint.ckpt").exists()
            and not (out / t / "summary.json").exists()]


def done(out):
    return [t for t in TASKS if (out / t / "summary.json").exists()]


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        yield client


@pytest.fixture(scope="module")
def long_sweep(cli, tmp_path_factory):
    """The long plan, and its uninterrupted sweep's contents, which sweeps in base/out match."""
    base = tmp_path_factory.mktemp("long")
    plan = write_plan(base, **LONG)
    cli("sweep", plan, "-o", base / "out", "-q")
    return plan, base / "out", contents(set_aside(base / "out", "reference"))


def test_the_table_is_a_structured_array_without_pandas(cli, tmp_path, client, monkeypatch):
    plan = write_plan(tmp_path, **SHORT)
    out = tmp_path / "out"
    cli("sweep", plan, "-o", out, "-q")
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas raises ImportError
    table = carom.sweep(plan, out, client=client)  # every task done: only reads results.csv
    assert isinstance(table, np.ndarray)
    assert column_names(table)[:3] == ["phi", "seed", "status"]
    assert table["phi"].dtype == float and table["seed"].dtype == np.int64
    assert list(table["status"]) == ["done"] * 4 and np.all(table["Z"] > 1)


def test_cli_mpi_and_dask_write_the_same_files(cli, tmp_path, client):
    plan = write_plan(tmp_path, **SHORT)
    out = tmp_path / "out"
    cli("sweep", plan, "-o", out, "-q")
    ways = {"carom sweep": contents(set_aside(out, "cli"))}
    if has_mpi(cli):
        proc = mpi_sweep(cli, plan, "-o", out, "-q")
        assert proc.returncode == 0, proc.stderr.decode()
        ways["mpirun -n 3"] = contents(set_aside(out, "mpi"))
    table = carom.sweep(plan, out, client=client)
    ways["carom.sweep"] = contents(out)
    for way, files in ways.items():
        assert_same_contents(files, ways["carom sweep"], way)

    # The table is results.csv, typed.
    rows = [line.split(",") for line in (out / "results.csv").read_text().splitlines()]
    assert column_names(table) == rows[0]
    assert list(table["phi"]) == [0.3, 0.3, 0.5, 0.5] and table["phi"].dtype == float
    assert list(table["seed"]) == [1, 2, 1, 2] and table["seed"].dtype == "int64"
    assert list(table["status"]) == ["done"] * 4 and list(table["error"]) == [""] * 4
    assert list(table["Z"]) == [float(row[3]) for row in rows[1:]]
    if "mpirun -n 3" not in ways:
        pytest.skip("no mpirun, or carom built without MPI: compared the other two only")


def test_a_folder_whose_name_is_not_utf8_gets_the_same_files(cli, tmp_path, client):
    """Regression: a sweep into dossier\\xe9 had every task fail ("invalid UTF-8 byte" writing its
    summary), and carom.sweep could not name such a folder at all, nor read a plan so named."""
    plan = os.fsdecode(os.fsencode(tmp_path) + b"/plan\xe9.toml")
    os.rename(write_plan(tmp_path, **SHORT), plan)
    out = os.fsdecode(os.fsencode(tmp_path) + b"/dossier\xe9")
    cli("sweep", plan, "-o", out, "-q")
    reference = contents(set_aside(Path(out), "cli"))
    table = carom.sweep(plan, out, client=client)
    assert list(table["status"]) == ["done"] * 4
    assert_same_contents(contents(Path(out)), reference, "carom.sweep")


@pytest.mark.parametrize("sampler", ["md", "ecmc"], ids=["dynamics", "chains"])
def test_each_task_is_its_commands_run_alone(cli, tmp_path, sampler):
    """Dynamics, and event chains (sampler = "ecmc"), each task's chains drawn by its own swept
    seed: four different runs, each ending in the start file `final` names."""
    (tmp_path / "sweep").mkdir()
    plan = write_plan(tmp_path / "sweep", PLAN.format(**SHORT).replace(
        "[run]\n", f'[run]\nsampler = "{sampler}"\nfinal = "end.gsd"\n'))
    cli("sweep", plan, "-o", "out", "-q", cwd=tmp_path / "sweep")
    swept = contents(tmp_path / "sweep" / "out")
    alone = tmp_path / "alone"
    env = dict(os.environ, PATH=f"{Path(cli.exe).parent}{os.pathsep}{os.environ['PATH']}")
    for task in TASKS:
        # The same relative layout elsewhere: the commands' paths are the sweep's.
        (alone / "out" / task).mkdir(parents=True)
        commands = tmp_path / "sweep" / "out" / task / "task.txt"
        proc = subprocess.run(["bash", "-e", str(commands)], cwd=alone, env=env,
                              capture_output=True, timeout=60)
        assert proc.returncode == 0, proc.stderr.decode()
        for name in TASK_FILES:
            assert (alone / "out" / task / name).read_bytes() == swept[f"{task}/{name}"], \
                f"{task}/{name}"
        assert (alone / "out" / task / "end.gsd").read_bytes() == \
            (tmp_path / "sweep" / "out" / task / "end.gsd").read_bytes()
        summary = json.loads((alone / "out" / task / "summary.json").read_text())
        assert {k: v for k, v in summary.items() if k not in CLOCK} \
            == swept[f"{task}/summary.json"], task
        assert summary["sampler"] == sampler
    distinct = {swept[f"{task}/summary.json"]["pair_collisions"] for task in TASKS}
    assert len(distinct) == len(TASKS)


FLUID_PLAN = """\
[start]
n = 64
phi = 0.2
boundary = "periodic"

[compress]
unit_diameter = true

[run]
sampler = "ecmc"
end_time = 20
equilibrate = 5

[sweep]
phi = [0.3, 0.5]
seed = [1, 2]
"""


def test_runs_from_compressed_starts_are_their_commands_alone_on_every_runner(cli, tmp_path,
                                                                               client):
    """[compress] and [run]: each task is carom init's gas, carom compress to the swept phi and
    carom run from the packing; the commands run alone, mpirun and Dask write the same files."""
    (tmp_path / "sweep").mkdir()
    plan = write_plan(tmp_path / "sweep", FLUID_PLAN)
    cli("sweep", plan, "-o", "out", "-q", cwd=tmp_path / "sweep")
    out = tmp_path / "sweep" / "out"
    swept = contents(out)
    alone = tmp_path / "alone"
    env = dict(os.environ, PATH=f"{Path(cli.exe).parent}{os.pathsep}{os.environ['PATH']}")
    for task in TASKS:
        (alone / "out" / task).mkdir(parents=True)
        commands = (out / task / "task.txt").read_text()
        assert [line.split()[1] for line in commands.splitlines()] == ["init", "compress", "run"]
        proc = subprocess.run(["bash", "-e", str(out / task / "task.txt")], cwd=alone, env=env,
                              capture_output=True, timeout=60)
        assert proc.returncode == 0, proc.stderr.decode()
        for name in TASK_FILES + ("packing.txt",):
            assert (alone / "out" / task / name).read_bytes() == (out / task / name).read_bytes(), \
                f"{task}/{name}"
        summary = json.loads((alone / "out" / task / "summary.json").read_text())
        assert {k: v for k, v in summary.items() if k not in CLOCK} == swept[f"{task}/summary.json"]
        assert summary["packing_fraction"] == pytest.approx(float(task[4:7]), abs=1e-12)
        compressions = [json.loads((folder / task / "compression.json").read_text())
                        for folder in (alone / "out", out)]
        assert [{k: v for k, v in c.items() if k not in CLOCK} for c in compressions] == \
            [{k: v for k, v in compressions[1].items() if k not in CLOCK}] * 2
        assert compressions[0]["status"] == "reached_target"
    # The runners, each into the same absolute folder (the files name it).
    set_aside(out, "alone_reference")
    cli("sweep", plan, "-o", out, "-q")
    reference = contents(set_aside(out, "cli"))
    ways = {}
    if has_mpi(cli):
        proc = mpi_sweep(cli, plan, "-o", out, "-q")
        assert proc.returncode == 0, proc.stderr.decode()
        ways["mpirun -n 3"] = contents(set_aside(out, "mpi"))
    carom.sweep(plan, out, client=client)
    ways["carom.sweep"] = contents(out)
    for way, files in ways.items():
        assert_same_contents(files, reference, way)
    assert carom._carom.SweepPlan.read(os.fsencode(plan)).compresses_start


@pytest.mark.parametrize("how", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_a_sweep_killed_or_stopped_goes_on_to_the_same_files(cli, long_sweep, how):
    plan, out, reference = long_sweep
    shutil.rmtree(out, ignore_errors=True)
    sweep = sweep_process(cli, plan, out)
    # Some task done, another mid-run with a checkpoint.
    wait_until(lambda: done(out) and running(out), sweep)
    sweep.send_signal(how)
    err = sweep.communicate(timeout=60)[1].decode()
    if how == signal.SIGKILL:
        assert sweep.returncode == -signal.SIGKILL
    else:
        # Every running task saved, then exit 128 + 15.
        assert sweep.returncode == 128 + signal.SIGTERM, err
        assert "run the same command again" in err, err
    assert len(done(out)) < len(TASKS)
    cli("sweep", plan, "-o", out, "-q")
    assert_same_contents(contents(out), reference, f"after {how.name}")


def test_tasks_stopped_at_their_end_are_rerun_to_the_same_files(cli, tmp_path):
    """Regression: a stop that landed once a task had reached its end, after its final
    checkpoint and before its summary (how the SIGTERM case above failed now and then on a
    loaded machine), left a checkpoint without the window's records: the rerun wrote a summary
    without the drift verdict and the pressure tensor's errors, and the task was done. Tasks
    caught there (their final checkpoint saved, no summary yet) rerun to the sweep's files."""
    plan = write_plan(tmp_path, **SHORT)
    out = tmp_path / "out"
    cli("sweep", plan, "-o", out, "-q")
    reference = contents(out)
    for task in TASKS:
        assert reference[f"{task}/summary.json"]["compressibility_factor_drift"] is not None
        (out / task / "summary.json").unlink()
    cli("sweep", plan, "-o", out, "-q")
    assert_same_contents(contents(out), reference, "rerun from the end")


def test_a_sweep_with_a_gsd_dump_killed_goes_on_to_the_same_files(cli, tmp_path):
    """Regression: a sweep with a .gsd dump could never be resumed: every rerun failed its
    tasks ("a resumed run cannot continue a .gsd trajectory yet"). Killed mid-run, it reruns to
    the files of the sweep never killed, the dumps byte for byte."""
    text = PLAN.format(**LONG).replace("\n[sweep]", 'dump = "movie.gsd"\nevery = 60\n\n[sweep]')
    plan = write_plan(tmp_path, text)
    out = tmp_path / "out"
    cli("sweep", plan, "-o", out, "-q")
    reference = set_aside(out, "reference")
    movies = {task: (reference / task / "movie.gsd").read_bytes() for task in TASKS}
    reference = contents(reference)
    sweep = sweep_process(cli, plan, out)
    wait_until(lambda: running(out), sweep)
    sweep.kill()
    sweep.communicate(timeout=60)
    cli("sweep", plan, "-o", out, "-q")
    assert_same_contents(contents(out), reference, "killed")
    for task in TASKS:
        assert (out / task / "movie.gsd").read_bytes() == movies[task], task


def test_a_dask_worker_killed_mid_task_changes_nothing(long_sweep, client):
    plan, out, reference = long_sweep
    shutil.rmtree(out, ignore_errors=True)
    pids = client.run(os.getpid)
    killed = []

    def kill_a_busy_worker():
        # Once each worker runs a task that has a checkpoint.
        while len(done(out)) < len(TASKS):
            busy = [address for address, keys in client.processing().items() if keys]
            if len(running(out)) == len(busy) == len(pids):
                os.kill(pids[busy[0]], signal.SIGKILL)
                killed.append(pids[busy[0]])
                return
            time.sleep(0.002)

    killer = threading.Thread(target=kill_a_busy_worker)
    killer.start()
    table = carom.sweep(plan, out, client=client)
    killer.join()
    assert killed, "the tasks ended before a worker could be killed"
    assert killed[0] not in client.run(os.getpid).values()
    assert list(table["status"]) == ["done"] * len(TASKS)
    assert_same_contents(contents(out), reference, "a worker killed")


CTRL_C = textwrap.dedent("""
    import os, signal, sys, threading
    from carom import _carom

    plan, out = _carom.SweepPlan.read(sys.argv[1]), sys.argv[2]
    task = os.path.join(out, plan.tasks[2])
    threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
    try:
        _carom.run_task(plan, 2, out)
        print("returned")
    except KeyboardInterrupt:
        print("KeyboardInterrupt", os.path.exists(os.path.join(task, "checkpoint.ckpt")),
              os.path.exists(os.path.join(task, "summary.json")))
    print(*_carom.run_task(plan, 2, out))
""")


def test_ctrl_c_stops_a_task_and_it_goes_on_to_the_same_files(long_sweep):
    plan, out, reference = long_sweep
    shutil.rmtree(out, ignore_errors=True)
    child = subprocess.run([sys.executable, "-c", CTRL_C, str(plan), str(out)],
                           capture_output=True, text=True, timeout=60)
    assert child.returncode == 0, child.stderr
    # Stopped mid-run, its checkpoint saved; run again, it ended as it would have.
    assert child.stdout.splitlines() == ["KeyboardInterrupt True False", "done "], child.stdout
    task = TASKS[2]
    for name in TASK_FILES:
        assert (out / task / name).read_bytes() == reference[f"{task}/{name}"], name
    summary = json.loads((out / task / "summary.json").read_text())
    assert {k: v for k, v in summary.items() if k not in CLOCK} \
        == reference[f"{task}/summary.json"]


BAD_PLANS = {
    # (what replaces what in PLAN, the line and key the error names)
    "unknown option": (('boundary = "periodic"', 'boundary = "periodic"\ncolour = "red"'), 4,
                       "[start] colour"),
    "empty axis": (("phi = [0.3, 0.5]", "phi = []"), 11, "[sweep] phi"),
    "bad value in one task": (("phi = [0.3, 0.5]", "phi = [0.3, 2.0]"), 11, "[sweep] phi = 2"),
    # A dotted key 100,000 deep crashed the TOML parser (and Python with it).
    "deep nesting": (("seed = [1, 2]", "seed = [1, 2]\nx" + ".x" * 100_000 + " = 1"), 13,
                     "nesting deeper than"),
}


@pytest.mark.parametrize("change,line,key", BAD_PLANS.values(), ids=BAD_PLANS.keys())
def test_a_bad_plan_is_refused_naming_its_line(cli, tmp_path, change, line, key):
    text = PLAN.format(**SHORT).replace(*change)
    assert text != PLAN.format(**SHORT)
    plan = write_plan(tmp_path, text)
    cli("sweep", "plan.toml", "-o", "out", expect=2, cwd=tmp_path)
    assert cli.last_stderr.startswith(f"carom: error: plan.toml:{line}: {key}"), cli.last_stderr
    with pytest.raises(ValueError, match=re.escape(f"{plan}:{line}: {key}")):
        carom.sweep(plan, tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_a_task_that_cannot_run_fails_alone(cli, tmp_path, client):
    # Random placement cannot reach phi = 0.7 in 2D: it jams.
    plan = write_plan(tmp_path, PLAN.format(**SHORT).replace(
        'boundary = "periodic"', 'boundary = "periodic"\nrandom = true').replace(
        "phi = [0.3, 0.5]", "phi = [0.3, 0.7]").replace("seed = [1, 2]", ""))
    cli("sweep", plan, "-o", tmp_path / "cli", "-q", expect=101)
    assert "task phi=0.7 failed: random placement jammed" in cli.last_stderr
    rows = (tmp_path / "cli" / "results.csv").read_text().splitlines()
    assert rows[1].split(",")[:2] == ["0.3", "done"]
    assert rows[2].startswith("0.7,failed,,") and "random placement jammed" in rows[2]

    table = carom.sweep(plan, tmp_path / "dask", client=client)
    assert (tmp_path / "dask" / "results.csv").read_bytes() \
        == (tmp_path / "cli" / "results.csv").read_bytes()
    assert list(table["status"]) == ["done", "failed"]
    assert table["Z"][0] > 1 and np.isnan(table["Z"][1])
    assert table["error"][1] == rows[2].split(",", 11)[-1]


# A compression that jams short of its target at the fast rate: its error names its packing's
# path, here in a folder whose name is not UTF-8.
JAMMING_PLAN = """\
[start]
n = 64
phi = 0.3
polydispersity = 0.2
boundary = "periodic"
[compress]
phi = 0.8
[sweep]
rate = [0.1, 1000]
"""


def jammed_sweep_by_the_cli(cli, tmp_path):
    """The plan, the folder caf\\xe9/out and the results.csv `carom sweep` writes there (then
    set aside): the second task failed, its error naming caf\\xe9/.../packing.txt."""
    plan = write_plan(tmp_path, JAMMING_PLAN)
    out = Path(os.fsdecode(os.fsencode(tmp_path) + b"/caf\xe9")) / "out"
    cli("sweep", plan, "-o", out, "-q", expect=101)
    results = (out / "results.csv").read_bytes()
    assert b"\n1000,failed," in results and b"caf\xe9/" in results, results
    set_aside(out, "cli")
    return plan, out, results


def test_a_failure_naming_a_non_utf8_path_is_recorded_under_mpi(cli, tmp_path):
    """Regression: a worker rank could not send such an error (the json of its report threw) and
    rank 0 waited for it for ever."""
    if not has_mpi(cli):
        pytest.skip("no mpirun, or carom built without MPI")
    plan, out, results = jammed_sweep_by_the_cli(cli, tmp_path)
    mpi = mpi_sweep(cli, plan, "-o", out, "-q")
    assert mpi.returncode == 101, mpi.stderr.decode(errors="replace")
    assert (out / "results.csv").read_bytes() == results


def test_a_failure_naming_a_non_utf8_path_is_recorded_on_dask(cli, tmp_path, client):
    """Regression: the error reached Python as a UnicodeDecodeError on the worker, which aborted
    the whole carom.sweep."""
    plan, out, results = jammed_sweep_by_the_cli(cli, tmp_path)
    table = carom.sweep(plan, out, client=client)
    assert list(table["status"]) == ["done", "failed"]
    assert (out / "results.csv").read_bytes() == results


def test_bad_arguments_are_refused(tmp_path):
    plan = write_plan(tmp_path, **SHORT)
    with pytest.raises(ValueError, match="plan must be a path"):
        carom.sweep(1, tmp_path / "out")
    with pytest.raises(ValueError, match="out_dir must be a path"):
        carom.sweep(plan, None)
    with pytest.raises(ValueError, match="client must be a dask.distributed Client"):
        carom.sweep(plan, tmp_path / "out", client="tcp://127.0.0.1:8786")
    with pytest.raises(ValueError, match="cannot read the plan"):
        carom.sweep(tmp_path / "missing.toml", tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_a_sweep_under_mpi_records_what_fails_as_without_it(cli, tmp_path):
    """A task whose failure never reaches its error.txt (here its error.txt is a folder that
    cannot be removed) is failed, with the same error and exit code, whatever ran it."""
    if not has_mpi(cli):
        pytest.skip("no mpirun, or carom built without MPI")
    plan = write_plan(tmp_path, **SHORT)
    for way in ("alone", "mpi"):
        (tmp_path / way / TASKS[1] / "error.txt" / "x").mkdir(parents=True)
    alone = subprocess.run([cli.exe, "sweep", str(plan), "-o", "alone", "-q"], cwd=tmp_path,
                           capture_output=True, timeout=120)
    mpi = mpi_sweep(cli, plan, "-o", "mpi", "-q", cwd=tmp_path)
    assert alone.returncode == 101, alone.stderr.decode()
    assert mpi.returncode == alone.returncode, mpi.stderr.decode()
    rows = (tmp_path / "alone" / "results.csv").read_text().splitlines()
    assert rows[2].startswith("0.3,2,failed,") and "error.txt" in rows[2], rows[2]
    assert (tmp_path / "mpi" / "results.csv").read_text().replace("mpi/", "alone/") \
        == (tmp_path / "alone" / "results.csv").read_text()


def test_a_failure_that_never_reached_its_error_file_is_recorded_on_dask(cli, tmp_path, client):
    """Regression: carom.sweep read the tasks' folders again instead of what its workers
    returned, so a task whose error.txt could not be written (here a folder that cannot be
    removed) was not failed as `carom sweep` records it."""
    plan = write_plan(tmp_path, **SHORT)
    out = tmp_path / "out"
    blocked = out / TASKS[1] / "error.txt" / "x"
    blocked.mkdir(parents=True)
    cli("sweep", plan, "-o", out, "-q", expect=101)
    results = (out / "results.csv").read_bytes()
    set_aside(out, "cli")
    blocked.mkdir(parents=True)
    table = carom.sweep(plan, out, client=client)
    assert list(table["status"]) == ["done", "failed", "done", "done"]
    assert (out / "results.csv").read_bytes() == results


def refusal(cli, *args, cwd):
    """The first line of a command's error (exit 2) run in cwd, after 'carom: error: '."""
    cli(*args, expect=2, cwd=cwd)
    first = cli.last_stderr.splitlines()[0]
    assert first.startswith("carom: error: "), cli.last_stderr
    return first[len("carom: error: "):]


def test_a_start_frame_named_in_capitals_is_an_input_all_the_same(cli, tmp_path):
    """A start `FILE.GSD:K` is the file FILE.GSD however its ending is spelled, as carom run reads
    it: --html naming it is refused before any task runs, and the file is left as it was."""
    cli("init", "--n", "64", "--phi", "0.3", "--seed", "1", "-o", "gas.txt", cwd=tmp_path)
    cli("run", "gas.txt", "1", "--final", "START.GSD", "-q", cwd=tmp_path)
    start = (tmp_path / "START.GSD").read_bytes()
    write_plan(tmp_path, '[start]\nfile = "START.GSD:0"\n[run]\nend_time = 1\n[sweep]\n'
                         'kT = [1.0, 2.0]\n')
    why = refusal(cli, "sweep", "plan.toml", "-o", "out", "--html", "START.GSD", cwd=tmp_path)
    assert "name the same file" in why and "the start file" in why, why
    assert (tmp_path / "START.GSD").read_bytes() == start
    assert not (tmp_path / "out").exists()


def test_an_output_that_is_an_input_or_the_sweeps_own_file_is_refused(cli, tmp_path):
    """--html naming the plan, a table or a task's file, however spelled, and an -o whose tables
    would be the plan: refused (exit 2) before any task runs, nothing overwritten."""
    plan = write_plan(tmp_path, **SHORT)
    cli("sweep", "plan.toml", "-o", "out", "-q", cwd=tmp_path)
    out = tmp_path / "out"
    before = {p: p.read_bytes() for p in [plan, *out.rglob("*")] if p.is_file()}
    (tmp_path / "link.html").symlink_to(out / TASKS[0] / "summary.json")
    os.link(out / "summary.csv", tmp_path / "hard.html")
    for page in ["plan.toml", "./plan.toml", "out/results.csv", f"out/../out/{TASKS[1]}/log.csv",
                 f"out/{TASKS[0]}/checkpoint.ckpt", "link.html", "hard.html",
                 f"out/{TASKS[2]}/task.txt"]:
        why = refusal(cli, "sweep", "plan.toml", "-o", "out", "--html", page, cwd=tmp_path)
        assert "name the same file" in why and "--html" in why, why
    # A plan named as the sweep's table, in the sweep's folder.
    shutil.copy(plan, tmp_path / "results.csv")
    why = refusal(cli, "sweep", "results.csv", "-o", ".", cwd=tmp_path)
    assert "results.csv" in why and "the plan" in why, why
    with pytest.raises(ValueError, match="name the same file"):
        carom.sweep(tmp_path / "results.csv", tmp_path)
    mpi = mpi_sweep(cli, "plan.toml", "-o", "out", "--html", "plan.toml", cwd=tmp_path)
    assert mpi is None or (mpi.returncode == 2 and b"name the same file" in mpi.stderr)
    assert (tmp_path / "results.csv").read_bytes() == plan.read_bytes()
    assert {p: p.read_bytes() for p in [plan, *out.rglob("*")] if p.is_file()} == before


def test_output_locations_are_checked_before_any_task_runs(cli, tmp_path):
    plan = write_plan(tmp_path, **SHORT)
    (tmp_path / "file").write_text("not a folder")
    why = cli.error("sweep", plan, "-o", tmp_path / "file")
    assert "is a file" in why, why
    why = cli.error("sweep", plan, "-o", tmp_path / "file" / "out")
    assert "is a file" in why, why
    with pytest.raises(ValueError, match="is a file"):
        carom.sweep(plan, tmp_path / "file")
    why = cli.error("sweep", plan, "-o", tmp_path / "out", "--html", "/nonexistent/r.html")
    assert "/nonexistent" in why, why
    assert not (tmp_path / "out").exists()
    (tmp_path / "out" / "results.csv").mkdir(parents=True)
    why = cli.error("sweep", plan, "-o", tmp_path / "out")
    assert "results.csv" in why and "folder" in why, why
    assert list((tmp_path / "out").iterdir()) == [tmp_path / "out" / "results.csv"]
    assert (tmp_path / "file").read_text() == "not a folder"


def test_ctrl_c_while_the_tasks_are_submitted_stops_those_submitted(tmp_path, client,
                                                                    monkeypatch):
    """Regression: the tasks were submitted outside the try that stops them, so a Ctrl-C then
    left those already submitted running on the workers."""
    plan = write_plan(tmp_path, **LONG)
    submitted = []
    submit = client.submit

    def interrupted_submit(*args, **kwargs):
        if submitted:
            raise KeyboardInterrupt
        submitted.append(submit(*args, **kwargs))
        return submitted[-1]

    stopped = []
    run = client.run

    def recorded_run(function, *args, **kwargs):
        stopped.append(function.__name__)
        return run(function, *args, **kwargs)

    monkeypatch.setattr(client, "submit", interrupted_submit)
    monkeypatch.setattr(client, "run", recorded_run)
    with pytest.raises(KeyboardInterrupt):
        carom.sweep(plan, tmp_path / "out", client=client)
    monkeypatch.undo()
    assert stopped == ["_stop_sweep_tasks"]
    assert submitted[0].cancelled()


def test_a_second_sweep_in_a_busy_folder_is_refused(cli, tmp_path):
    """Another sweep holds the folder (its sweep.lock): refused before anything runs, however
    the sweep is run; once the holder has gone (even killed), the folder is free. The holder's
    POSIX lock (lockf) conflicts with the sweep's open file description lock, as flock would
    not."""
    import fcntl

    plan = write_plan(tmp_path, **SHORT)
    out = tmp_path / "out"
    out.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", textwrap.dedent("""
        import fcntl, sys
        f = open(sys.argv[1], "a")
        fcntl.lockf(f, fcntl.LOCK_EX)
        print("held", flush=True)
        sys.stdin.read()
        """), str(out / "sweep.lock")], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    assert holder.stdout.readline() == b"held\n"
    why = cli.error("sweep", plan, "-o", out, "-q")
    assert "another sweep is running in" in why, why
    with pytest.raises(ValueError, match="another sweep is running in"):
        carom.sweep(plan, out)
    mpi = mpi_sweep(cli, plan, "-o", out, "-q")
    assert mpi is None or (mpi.returncode == 2 and b"another sweep is running in" in mpi.stderr)
    assert sorted(p.name for p in out.iterdir()) == ["sweep.lock"]
    holder.kill()
    holder.wait()
    cli("sweep", plan, "-o", out, "-q")
    with open(out / "sweep.lock", "a") as f:
        fcntl.lockf(f, fcntl.LOCK_EX | fcntl.LOCK_NB)  # free once the sweep has ended
    assert done(out) == list(TASKS)


def test_ctrl_c_stops_the_tasks_on_the_dask_workers(cli, long_sweep, client):
    """Ctrl-C in carom.sweep: the tasks its workers run stop too (a cancelled future does not stop
    a worker's thread), so that a sweep run again at once does not write a task together with a
    worker of the first: it goes on to the same files."""
    plan, out, reference = long_sweep
    shutil.rmtree(out, ignore_errors=True)
    pids = client.run(os.getpid)

    # Ctrl-C only once every worker runs a task: a signal sent after the sweep has returned would
    # land outside pytest.raises. Given up on, the test fails on the flag instead.
    gave_up = threading.Event()

    def interrupt_once_tasks_run():
        deadline = time.monotonic() + 60
        while len(running(out)) < len(pids):
            if time.monotonic() > deadline:
                gave_up.set()
                return
            time.sleep(0.002)
        os.kill(os.getpid(), signal.SIGINT)

    interrupter = threading.Thread(target=interrupt_once_tasks_run)
    interrupter.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            carom.sweep(plan, out, client=client)
    finally:
        interrupter.join()
    assert not gave_up.is_set(), "the workers were not caught running their tasks"
    stopped = running(out)
    assert stopped, "no task was caught running"
    # Every task the workers ran has let go of its folder, and none goes on.
    import fcntl
    for task in stopped:
        with open(out / task / "task.lock", "a") as f:
            fcntl.lockf(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
    cli("sweep", plan, "-o", out, "-q")
    assert_same_contents(contents(out), reference, "after Ctrl-C")


def test_a_task_whose_blocks_are_correlated_is_warned_of():
    """carom.sweep names a task whose Z_correlation is past _carom.CORRELATION_WARNING, as carom
    sweep does, unless it drifted (that warning says more); NaN (no verdict) is no warning."""
    from carom import dask_sweep

    class Plan:
        tasks = ["remembers", "drifted", "independent", "no verdict"]
    table = np.array([(0.5, 2.5), (4.0, 3.0), (0.1, 1.5), (np.nan, np.nan)],
                     dtype=[("Z_drift", float), ("Z_correlation", float)])
    with pytest.warns(carom.UnsettledWarning) as caught:
        dask_sweep._warn_of_unsettled(Plan, table)
    assert [str(w.message).split(":")[0] for w in caught] == ["task remembers", "task drifted"]
    assert "Z's blocks are correlated (Z_correlation = 2.50)" in str(caught[0].message)
    assert "Z drifted by 4.0" in str(caught[1].message)
    assert carom._carom.unsettled_warning(0.5, 1.5) is None


DRIFTING_PLAN = """\
[start]
n = 400
boundary = "periodic"

[run]
end_time = 10
equilibrate = 0
rule = "elastic"

[sweep]
phi = [0.68]
seed = [1, 2]
"""


def test_tasks_whose_z_drifted_are_flagged_in_the_tables_the_console_and_python(cli, tmp_path,
                                                                              client):
    """Disks at 0.68 melting from init's lattice, measured from t = 0: Z rises by several standard
    errors between the halves of the window. results.csv shows each task's drift (the summary's
    verdict), summary.csv counts the state point's drifted tasks, the report names them, and both
    `carom sweep` and carom.sweep warn; a settled sweep warns of nothing."""
    plan = write_plan(tmp_path, DRIFTING_PLAN)
    out = tmp_path / "out"
    cli("sweep", plan, "-o", out)
    names = ("phi=0.68,seed=1", "phi=0.68,seed=2")
    drifts = [json.loads((out / name / "summary.json").read_text())
              ["compressibility_factor_drift"]["sigmas"] for name in names]
    assert all(abs(d) > carom._carom.DRIFT_WARNING for d in drifts), drifts
    for name, drift in zip(names, drifts):
        assert f"warning: task {name}: Z drifted by {drift:.1f} standard errors" in cli.last_stderr
    assert "2 with Z drifting (column Z_drift)" in cli.last_stderr
    printed = [line[len("carom: warning: "):] for line in cli.last_stderr.splitlines()
               if line.startswith("carom: warning: task")]
    rows = (out / "results.csv").read_text().splitlines()
    header = rows[0].split(",")
    assert [float(r.split(",")[header.index("Z_drift")]) for r in rows[1:]] == drifts
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[0].endswith(",drifted") and summary[1].endswith(",2"), summary
    report = (out / "report.html").read_text()
    assert "Tasks whose Z drifted" in report and all(f"<b>{n}</b>" in report for n in names)
    cli("sweep", plan, "-o", out, "-q")
    assert cli.last_stderr == ""
    with pytest.warns(carom.UnsettledWarning,
                      match=r"task phi=0\.68,seed=1: Z drifted by") as caught:
        table = carom.sweep(plan, out, client=client)
    assert list(table["Z_drift"]) == drifts
    # In the console's words.
    assert [str(w.message) for w in caught if w.category is carom.UnsettledWarning] == printed

    settled = tmp_path / "settled"
    settled.mkdir()
    cli("sweep", write_plan(settled, **SHORT), "-o", settled / "out")
    assert "warning" not in cli.last_stderr and "drifting" not in cli.last_stderr
    assert all(abs(d) <= 3 for d in carom.sweep(settled / "plan.toml", settled / "out",
                                                  client=client)["Z_drift"])
