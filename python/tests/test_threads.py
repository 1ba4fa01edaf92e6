"""A Simulation running in one thread (GIL released) is not read or changed from another: every
public entry point that touches it refuses with RuntimeError while the run goes, and works again
once it has ended."""
import inspect
import threading
import time

import pytest

import carom


def calls(tmp_path):
    """Every public method of Simulation, and every module function taking one, with arguments
    that work on an idle simulation."""
    return {
        "run": lambda sim: sim.run(sim.time + 0.01),
        "advance": lambda sim: sim.advance(0.01),
        "collisions": lambda sim: sim.collisions(),
        "observables": lambda sim: sim.observables(),
        "reset_measurement": lambda sim: sim.reset_measurement(),
        "measure_from": lambda sim: sim.measure_from(sim.time),
        "format": lambda sim: sim.format("csv"),
        "save": lambda sim: sim.save(tmp_path / "saved.ckpt"),
        "__repr__": repr,
        "carom.compress": lambda sim: carom.compress(sim, phi=0.55),
    }


def properties():
    return [name for name, member in vars(carom.Simulation).items()
            if isinstance(member, property) and not name.startswith("_")]


def test_every_entry_point_is_listed(tmp_path):
    # A method added to Simulation must be added to calls() (and so to the test below).
    methods = {name for name, member in vars(carom.Simulation).items()
               if callable(member) and not name.startswith("_")}
    assert methods <= set(calls(tmp_path)), methods - set(calls(tmp_path))
    takes_a_simulation = {f"carom.{name}" for name in carom.__all__
                          if inspect.isfunction(getattr(carom, name))
                          and "sim" in inspect.signature(getattr(carom, name)).parameters}
    assert takes_a_simulation <= set(calls(tmp_path)), takes_a_simulation


def test_a_running_simulation_refuses_other_threads(tmp_path):
    sim = carom.init(n=20000, phi=0.5, boundary="periodic", rule="elastic")
    frames = tmp_path / "started.xyz"
    # The run writes its first frame (t = 0) as it begins: once that is on disk, it is running,
    # and it lasts seconds longer.
    worker = threading.Thread(target=sim.run, args=(60.0,),
                              kwargs=dict(dump=frames, every=100.0))
    worker.start()
    deadline = time.monotonic() + 30
    while not (frames.exists() and frames.stat().st_size > 0) and time.monotonic() < deadline:
        time.sleep(0.001)
    assert worker.is_alive(), "the run ended before it could be observed"
    refused = []
    for name in properties():
        with pytest.raises(RuntimeError, match="running"):
            getattr(sim, name)
        refused.append(name)
    for name, call in calls(tmp_path).items():
        with pytest.raises(RuntimeError, match="running"):
            call(sim)
        refused.append(name)
    assert worker.is_alive(), "the run ended while the calls were tried: make it longer"
    worker.join()
    assert sim.time == 60.0  # and it is usable again
    for name in properties():
        getattr(sim, name)
    for call in calls(tmp_path).values():
        call(sim)
    assert len(refused) > 25
