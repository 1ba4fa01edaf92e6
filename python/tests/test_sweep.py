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
    mpirun = shutil.which("mpirun")
    if mpirun and "sweep: MPI" in cli("--version"):
        # OpenMPI refuses to run as root unless told it may.
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        proc = subprocess.run([mpirun, "-n", "3", "--oversubscribe", cli.exe, "sweep", str(plan),
                               "-o", str(out), "-q"], capture_output=True, env=env, timeout=120)
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
    summary), and carom.sweep could not name such a folder at all."""
    plan = write_plan(tmp_path, **SHORT)
    out = os.fsdecode(os.fsencode(tmp_path) + b"/dossier\xe9")
    cli("sweep", plan, "-o", out, "-q")
    reference = contents(set_aside(Path(out), "cli"))
    table = carom.sweep(plan, out, client=client)
    assert list(table["status"]) == ["done"] * 4
    assert_same_contents(contents(Path(out)), reference, "carom.sweep")


def test_each_task_is_its_commands_run_alone(cli, tmp_path):
    (tmp_path / "sweep").mkdir()
    plan = write_plan(tmp_path / "sweep", **SHORT)
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
        summary = json.loads((alone / "out" / task / "summary.json").read_text())
        assert {k: v for k, v in summary.items() if k not in CLOCK} \
            == swept[f"{task}/summary.json"], task


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
    assert table["error"][1] == rows[2].split(",", 9)[-1]


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
