"""carom.sweep: `carom sweep` with its tasks handed out by Dask."""

import csv as _csv
import os as _os
import uuid as _uuid
import warnings as _warnings

import numpy as _np

from . import _carom
from .simulation import UnsettledWarning


def _file_name(name, value):
    if not isinstance(value, (str, _os.PathLike)):
        raise ValueError(f"{name} must be a path (str or os.PathLike), got {value!r}")
    return _os.fspath(value)


def _sweep_task(text, name, folder, out_dir, index, sweep_id):
    """One task of carom.sweep, on a Dask worker: the plan parsed again from its text (a worker
    needs to see out_dir, not the plan's file), then the task run, or continued from what an
    earlier attempt left, until done or until _stop_sweep_tasks(sweep_id). Returns (status,
    error). Whatever fails here is the task's failure, as `carom sweep` records it (a task lock
    that cannot be made, say), not the whole sweep's."""
    try:
        return _carom.run_task(_carom.SweepPlan.parse(text, name, folder), index, out_dir, sweep_id)
    except Exception as error:
        return "failed", str(error)


def _stop_sweep_tasks(sweep_id):
    """On a Dask worker: stops the tasks of the sweep `sweep_id`, running or to come (each saves
    its checkpoint)."""
    _carom.stop_tasks(sweep_id)


def _typed(text, kind):
    """A swept value as results.csv writes it, as the plan types it (like `kind`)."""
    if isinstance(kind, bool):
        return text == "true"
    if isinstance(kind, list):
        return [float(x) for x in text.split()]
    return type(kind)(text)


def _results_table(plan, path):
    """results.csv as a pandas DataFrame, or as a numpy structured array without pandas: the swept
    keys typed as in the plan, status and error as text, every measure a float (NaN: none)."""
    # A task's error may name a file whose name is not UTF-8: read as os.fsdecode would.
    with open(path, newline="", encoding="utf-8", errors="surrogateescape") as f:
        header, *rows = list(_csv.reader(f))
    first = plan.points[0]
    columns = {}
    for k, name in enumerate(header):
        texts = [row[k] for row in rows]
        if name in first:
            values = [_typed(text, first[name]) for text in texts]
            if isinstance(first[name], list):
                column = _np.empty(len(values), dtype=object)
                column[:] = values
            else:
                column = _np.array(values)
        elif name in ("status", "error"):
            column = _np.array(texts, dtype=str)
        else:
            column = _np.array([float(text) if text else _np.nan for text in texts])
        columns[name] = column
    try:
        import pandas
    except ImportError:
        table = _np.empty(len(rows), dtype=[(name, c.dtype) for name, c in columns.items()])
        for name, column in columns.items():
            table[name] = column
        return table
    return pandas.DataFrame(columns)


def sweep(plan, out_dir, client=None):
    """`carom sweep PLAN -o OUT_DIR` with its tasks handed out by Dask: the same folder, the same
    files, byte for byte, and its results.csv as a table.

    plan: a plan file (TOML), as `carom sweep` reads it (`carom sweep --help` describes it): a
    [start], a [run] or a [compress] (or both: each run from its start compressed), and the
    [sweep] axes whose every combination is a task. A
    bad plan raises ValueError naming the file, line and key, before anything runs; so does an
    out_dir whose task folders hold another plan's tasks, an out_dir that cannot be a folder (a
    file), an out_dir whose files would overwrite the plan or a start file, and an out_dir
    another sweep is running in (its sweep.lock held).

    Each task not yet done is a Dask task (pure=False) that runs it in out_dir/<task>/ exactly as
    `carom sweep` would, on whatever worker gets it: workers must see out_dir and a start `file`
    the plan names (relative paths are taken from each worker's working folder: give absolute
    ones on a shared file system for a cluster), not the plan itself.

    client: a dask.distributed Client; None makes a LocalCluster of one single-threaded worker
    process per core, closed at the end. The tasks are resumable, as
    `carom sweep`'s are: a worker that dies mid-task has the task rerun by Dask elsewhere (the
    scheduler's allowed-failures), continuing it from its checkpoint. Ctrl-C stops the sweep's
    tasks on the workers too (each saves its checkpoint) and raises KeyboardInterrupt once none
    runs any more; called again, by carom.sweep or `carom sweep`, the sweep runs only what is not
    done. A task holds its folder's task.lock while it runs, so that no two ever write one task
    (a task still held, by a worker of an earlier sweep, is waited for). A task that fails (a
    start its options cannot make, a compression that jams short of its `phi`) raises nothing:
    its row says status "failed" and why.

    Then out_dir/results.csv, summary.csv and report.html are written, as `carom sweep` writes
    them, and results.csv is returned: a pandas DataFrame (a numpy structured array without
    pandas), a row a task in the plan's order, with the swept keys as the plan types them, status
    ("done", "failed"), the measures as floats (NaN: not measured) and the error.
    """
    plan = _file_name("plan", plan)
    # The library is given the folder's bytes: its name need not be UTF-8.
    out_dir = _os.fsencode(_file_name("out_dir", out_dir))
    import distributed  # here: only a sweep needs Dask, which takes a second to import
    if client is not None and not isinstance(client, distributed.Client):
        raise ValueError(f"client must be a dask.distributed Client or None, got {client!r}")
    core = _carom.SweepPlan.read(_os.fsencode(plan))
    # The folder checked, made and locked (no other sweep, carom.sweep, carom sweep or carom_mpi,
    # runs in it meanwhile), as by every runner of a sweep.
    with _carom.prepare_sweep(core, out_dir) as prepared:
        waiting = prepared.waiting
        returned = []
        if waiting:
            if client is None:
                with distributed.LocalCluster(n_workers=_os.cpu_count() or 1,
                                              threads_per_worker=1, processes=True) as cluster, \
                        distributed.Client(cluster) as own:
                    returned = _run_tasks(own, core, out_dir, waiting)
            else:
                returned = _run_tasks(client, core, out_dir, waiting)
        results = _carom.returned_results(
            core, out_dir, waiting,
            [_carom.TaskResult(status, _os.fsencode(error)) for status, error in returned])
        _carom.finish_sweep(core, out_dir, results)
    table = _results_table(core, _os.path.join(out_dir, b"results.csv"))
    _warn_of_unsettled(core, table)
    return table


def _warn_of_unsettled(plan, table):
    """A warning for each task whose Z drifted past _carom.DRIFT_WARNING standard errors over its
    measurement window, or else whose blocks were correlated past _carom.CORRELATION_WARNING, in
    the words `carom sweep` prints (_carom.unsettled_warning)."""
    names = table.dtype.names if isinstance(table, _np.ndarray) else list(table.columns)
    if "Z_drift" not in names:
        return
    for name, drift, memory in zip(plan.tasks, table["Z_drift"], table["Z_correlation"]):
        message = _carom.unsettled_warning(float(drift), float(memory))
        if message is not None:
            _warnings.warn(f"task {name}: {message}", UnsettledWarning, stacklevel=3)


def _run_tasks(client, plan, out_dir, indices):
    """The tasks `indices` of plan on client's workers, until every one has returned: what each
    returned, (status, error)."""
    sweep_id = _uuid.uuid4().hex
    futures = []
    try:
        for i in indices:
            futures.append(client.submit(_sweep_task, plan.text, plan.name, plan.folder, out_dir, i,
                                         sweep_id, pure=False))
        return client.gather(futures)
    except BaseException:
        # Stopped (Ctrl-C, while the tasks are submitted too) or refused. A cancelled future does
        # not stop a task a worker runs, so every worker is told to stop this sweep's tasks (each
        # saves its checkpoint), nothing is left queued on a client that outlives the sweep, and
        # the sweep returns once every task has let go of its folder: a sweep run again at once
        # finds them free.
        # A worker that cannot be reached (dead, restarting) is skipped: the wait below still
        # waits for any task it holds.
        client.run(_stop_sweep_tasks, sweep_id, on_error="ignore")
        client.cancel(futures)
        _carom.wait_for_tasks(plan, out_dir, indices)
        raise
