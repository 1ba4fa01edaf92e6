"""A Simulation running in one thread (GIL released) is not read or changed from another."""
import threading
import time

import pytest

import carom


def test_a_running_simulation_refuses_other_threads():
    sim = carom.init(n=20000, phi=0.5, boundary="periodic", rule="elastic")
    worker = threading.Thread(target=sim.run, args=(3.0,))
    worker.start()
    deadline = time.monotonic() + 30
    while not sim._running and worker.is_alive() and time.monotonic() < deadline:
        time.sleep(0.001)
    assert sim._running, "the run ended before it could be observed"
    with pytest.raises(RuntimeError, match="running"):
        sim.positions
    with pytest.raises(RuntimeError, match="running"):
        sim.run(4.0)
    worker.join()
    assert sim.time == 3.0  # and it is usable again
    sim.run(3.5)
