"""Ctrl-C during a long run raises KeyboardInterrupt promptly and leaves the simulation whole:
it saves, and run on it ends exactly as an uninterrupted run does. The run releases the GIL.

The interrupted run happens in a child interpreter, so that a binding that ignored SIGINT would
fail this test on a timeout instead of hanging the suite (or interrupting pytest itself)."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np

import carom
from _support import (assert_bitwise_equal, assert_same_run, assert_same_state, deterministic,
                      read_event_log)

START = dict(n=20000, phi=0.5, boundary="periodic", rule="elastic", seed=1)
EVERY = 2.0  # frames of the trajectory written during the interrupted run

CHILD = textwrap.dedent("""
    import json, os, shutil, signal, sys, threading, time
    import numpy as np
    import carom

    out = sys.argv[1]
    start = json.loads(sys.argv[2])
    every = float(sys.argv[3])
    sim = carom.init(**start)
    sent = []

    def interrupt():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    threading.Timer(0.5, interrupt).start()
    began = time.monotonic()
    try:
        sim.run(1e3, dump=os.path.join(out, "pieces.xyz"), every=every, collisions=True)
        outcome = "returned"
    except KeyboardInterrupt:
        outcome = "KeyboardInterrupt"
    caught = time.monotonic()
    report = dict(outcome=outcome, latency=caught - sent[0] if sent else None,
                  ran=caught - began, time=sim.time, events=sim.events)
    first_log = sim.collisions()
    # the trajectory as the interruption left it: every frame so far, flushed
    shutil.copy(os.path.join(out, "pieces.xyz"), os.path.join(out, "at_interruption.xyz"))
    # the state at the interruption, then saved and run on
    np.savez(os.path.join(out, "interrupted.npz"), positions=sim.positions,
             velocities=sim.velocities, log=first_log)
    sim.save(os.path.join(out, "interrupted.ckpt"))
    end = float(np.ceil(sim.time)) + 0.5
    rest_log = sim.run(end, dump=os.path.join(out, "pieces.xyz"), every=every, collisions=True)
    report.update(end=end, events_at_end=sim.events, observables=sim.observables(),
                  csv=sim.format("csv"))
    np.savez(os.path.join(out, "continued.npz"), positions=sim.positions,
             velocities=sim.velocities, wall_collisions=sim.wall_collisions,
             pair_collisions=sim.pair_collisions, log=np.concatenate([first_log, rest_log]))
    with open(os.path.join(out, "report.json"), "w") as f:
        json.dump(report, f)
""")


def test_ctrl_c_interrupts_and_the_run_goes_on_exactly(cli, tmp_path):
    child = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path), json.dumps(START),
                            repr(EVERY)], capture_output=True, text=True, timeout=60,
                           cwd=tmp_path)
    assert child.returncode == 0, child.stderr
    report = json.loads((tmp_path / "report.json").read_text())

    # Interrupted within a fraction of a second of the signal, mid-run.
    assert report["outcome"] == "KeyboardInterrupt"
    assert report["latency"] < 2.0, report
    assert 0.0 < report["time"] < 1e3 and report["events"] > 0
    end = report["end"]
    assert end > report["time"]

    # The uninterrupted run from the same start to the same end: bit for bit the same.
    whole = carom.init(**START)
    whole_log = whole.run(end, dump=tmp_path / "whole.xyz", every=EVERY, collisions=True)
    continued = np.load(tmp_path / "continued.npz")
    assert_bitwise_equal(continued["positions"], whole.positions, "positions")
    assert_bitwise_equal(continued["velocities"], whole.velocities, "velocities")
    assert_bitwise_equal(continued["wall_collisions"], whole.wall_collisions, "wall collisions")
    assert_bitwise_equal(continued["pair_collisions"], whole.pair_collisions, "pair collisions")
    assert report["events_at_end"] == whole.events
    assert deterministic(report["observables"]) == deterministic(whole.observables())
    assert report["csv"] == whole.format("csv")
    # the collision log (up to the interruption, then the rest) and the trajectory file too
    assert_bitwise_equal(continued["log"], whole_log, "collision log")
    interrupted = np.load(tmp_path / "interrupted.npz")
    assert len(interrupted["log"]) == report["events"]
    assert (tmp_path / "pieces.xyz").read_bytes() == (tmp_path / "whole.xyz").read_bytes()

    # The state at the interruption is a moment of the uninterrupted run.
    at_interruption = carom.init(**START)
    at_interruption.run(report["time"])
    assert at_interruption.events == report["events"]
    assert_bitwise_equal(interrupted["positions"], at_interruption.positions)
    assert_bitwise_equal(interrupted["velocities"], at_interruption.velocities)

    # The checkpoint saved after the interruption resumes to the same end, in Python and in the
    # command line.
    resumed = carom.resume(tmp_path / "interrupted.ckpt")
    assert resumed.time == report["time"] and resumed.events == report["events"]
    resumed.run(end)
    assert_same_run(resumed, whole)
    # `carom run --resume` continues the trajectory as it was at the interruption, to the very
    # file of the uninterrupted run
    frames = tmp_path / "at_interruption.xyz"
    assert frames.read_bytes().count(b"Time=") == int(report["time"] // EVERY) + 1
    assert cli("run", "--resume", tmp_path / "interrupted.ckpt", repr(end), "--format", "csv",
               "--dump", frames, "--every", repr(EVERY)) == whole.format("csv")
    assert frames.read_bytes() == (tmp_path / "whole.xyz").read_bytes()


def test_a_sigint_handler_of_ones_own_is_called_and_the_run_goes_on():
    # With a Python SIGINT handler that does not raise, Ctrl-C calls it during the run, which then
    # goes on to its end exactly; afterwards the handler is still the one SIGINT reaches.
    calls, sent = [], []

    def handler(signum, frame):
        calls.append(time.monotonic())

    def interrupt():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    end = 20.0  # a few seconds of work, so that the signal at 0.3 s comes during the run
    previous = signal.signal(signal.SIGINT, handler)
    try:
        sim = carom.init(**START)
        timer = threading.Timer(0.3, interrupt)
        timer.start()
        began = time.monotonic()
        sim.run(end)
        ended = time.monotonic()
        timer.join()
        assert ended - began > 0.4, "the run was too short to be interrupted"
        assert len(calls) == 1, calls
        assert began < calls[0] < ended and calls[0] - sent[0] < 0.5
        os.kill(os.getpid(), signal.SIGINT)  # outside any run: Python's handler as ever
        deadline = time.monotonic() + 2.0
        while len(calls) < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert len(calls) == 2
    finally:
        signal.signal(signal.SIGINT, previous)
    assert sim.time == end
    whole = carom.init(**START)
    whole.run(end)
    assert_same_run(sim, whole)


def test_the_gil_is_released_during_run():
    # Another Python thread keeps ticking while the main thread is inside sim.run.
    sim = carom.init(**START)
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.002)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        spans = []
        while sum(b - a for a, b in spans) < 0.5:
            began = time.monotonic()
            sim.run(sim.time + 1.0)
            spans.append((began, time.monotonic()))
    finally:
        stop.set()
        thread.join()
    inside = [t for t in ticks if any(a < t < b for a, b in spans)]
    duration = sum(b - a for a, b in spans)
    # at 2 ms a tick, a couple of hundred (a loaded machine may halve that); holding the GIL,
    # next to none
    assert len(inside) >= max(10, 0.05 * duration / 0.002), (len(inside), duration)


def test_a_run_in_a_thread_equals_a_run_in_the_main_thread():
    # Runs on worker threads (the GIL released) give the same results, concurrently.
    options = dict(n=500, phi=0.4, seed=81, boundary="periodic", rule="elastic")
    sims = [carom.init(**options) for _ in range(3)]
    threads = [threading.Thread(target=s.run, args=(5.0,)) for s in sims]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    alone = carom.init(**options)
    alone.run(5.0)
    for s in sims:
        assert_same_run(s, alone)


def test_cli_interrupt_checkpoint_resumes_in_python(cli, tmp_path):
    # SIGINT to `carom run --checkpoint`: the checkpoint it leaves resumes in Python exactly.
    start = tmp_path / "start.txt"
    cli("init", "--n", "20000", "--phi", "0.5", "--boundary", "periodic", "-o", start)
    proc = subprocess.Popen([cli.exe, "run", start, "1e6", "--rule", "elastic", "--boundary",
                             "periodic", "--checkpoint", tmp_path / "run.ckpt", "--events",
                             tmp_path / "events.csv", "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, err
    resumed = carom.resume(tmp_path / "run.ckpt")
    assert resumed.time > 0.0
    end = float(np.ceil(resumed.time)) + 0.5
    rest = resumed.run(end, collisions=True)
    whole = carom.read(start, rule="elastic", boundary="periodic")
    whole_log = whole.run(end, collisions=True)
    assert_same_state(resumed, whole)
    assert_bitwise_equal(np.concatenate([read_event_log(tmp_path / "events.csv"), rest]),
                         whole_log, "--events then the Python log")

