"""Helpers shared by the carom Python tests: bitwise comparisons and the command line's options."""

import csv
import json

import numpy as np

# The json fields that depend on the wall clock or on how the run was named, not on the physics.
NOT_DETERMINISTIC = ("input", "wall_seconds", "events_per_second")
# The transport coefficients' blocks are spaced by the run's end in windows too short for ten
# blocks of their lag (as these tests' are): runs cut into pieces that end elsewhere measure each
# piece's part of the window. (Z's drift verdict and errors are not: their blocks double as the
# window grows, whatever its end.)
PIECE_DEPENDENT = ("transport",)


# What a checkpoint keeps of its run's measurements that depends on the run's end (the transport
# blocks, the window and end they measure): a run in pieces has other ends, so its checkpoints
# differ from a run in one piece's there (and in the checksum that covers them).
PIECE_RECORDS = ("transport", "window_records", "checksum")


def checkpoint_state(data):
    """A checkpoint file's fields without its run's measurement records (PIECE_RECORDS)."""
    return {k: v for k, v in json.loads(data).items() if k not in PIECE_RECORDS}


def assert_bitwise_equal(a, b, what="arrays"):
    """Same dtype, shape and bytes: 0.0 and -0.0 differ, as do NaNs with different payloads."""
    a = np.ascontiguousarray(a)
    b = np.ascontiguousarray(b)
    assert a.dtype == b.dtype, f"{what}: dtype {a.dtype} != {b.dtype}"
    assert a.shape == b.shape, f"{what}: shape {a.shape} != {b.shape}"
    if a.tobytes() != b.tobytes():
        fa, fb = a.reshape(-1), b.reshape(-1)
        differ = (fa.view(np.uint8).reshape(fa.size, -1)
                  != fb.view(np.uint8).reshape(fb.size, -1)).any(axis=1)
        first = int(np.flatnonzero(differ)[0])
        where = np.unravel_index(first, a.shape)
        raise AssertionError(f"{what} differ in {int(differ.sum())} of {a.size} elements, first at "
                             f"{tuple(int(k) for k in where)}: {fa[first]!r} != {fb[first]!r}")


def deterministic(summary):
    """A json summary without the fields that legitimately differ between two equal runs (and
    the transport coefficients, which depend on how the run was cut)."""
    return {k: v for k, v in summary.items() if k not in NOT_DETERMINISTIC + PIECE_DEPENDENT}


def assert_same_state(a, b, what=""):
    """Two Simulations at the same instant with the same particles and counts, bit for bit."""
    assert a.time == b.time, f"{what}: time {a.time!r} != {b.time!r}"
    assert a.events == b.events, f"{what}: events {a.events} != {b.events}"
    for name in ("positions", "velocities", "radii", "masses", "wall_collisions",
                 "pair_collisions", "box"):
        assert_bitwise_equal(getattr(a, name), getattr(b, name), f"{what}: {name}")


def assert_same_run(a, b, what=""):
    """assert_same_state, and the same observables and output in every format."""
    assert_same_state(a, b, what)
    oa, ob = a.observables(), b.observables()
    assert list(oa) == list(ob), what
    assert deterministic(oa) == deterministic(ob), what
    assert a.format("csv") == b.format("csv"), what
    assert a.format("table") == b.format("table"), what
    assert json.loads(a.format("json"))["particles"] == json.loads(b.format("json"))["particles"]


def init_cli_args(**options):
    """carom.init's keyword arguments as `carom init` options."""
    args = []
    for key, value in options.items():
        if key == "placement":
            if value != "auto":
                args.append(f"--{value}")
        elif key == "box":
            args += ["--box", *[repr(float(v)) for v in value]]
        elif key in ("n", "phi", "seed", "dim", "boundary", "aspect", "radius", "polydispersity",
                     "kT"):
            args += [f"--{key}", repr(value) if isinstance(value, float) else str(value)]
        else:
            raise KeyError(key)
    return args


RUN_OPTIONS = ("rule", "boundary", "restitution", "tc", "engine")


def run_cli_args(**options):
    """carom.read's keyword arguments as `carom run` options."""
    args = []
    for key, value in options.items():
        if key not in RUN_OPTIONS:
            raise KeyError(key)
        args += [f"--{key}", repr(value) if isinstance(value, float) else str(value)]
    return args


LOG_DTYPE = np.dtype([("time", "<f8"), ("i", "<i8"), ("j", "<i8")])


def read_event_log(path):
    """A `carom run --events` csv as the structured array carom's run(collisions=True) returns,
    after checking that each row's kind agrees with its partner."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["time", "kind", "first", "partner"], rows[0]
    log = np.empty(len(rows) - 1, dtype=LOG_DTYPE)
    for k, (time, kind, first, partner) in enumerate(rows[1:]):
        assert kind == ("wall" if int(partner) < 0 else "pair"), (k, kind, partner)
        log[k] = (float(time), int(first), int(partner))
    return log


def particles_of(json_text):
    return json.loads(json_text)["particles"]
