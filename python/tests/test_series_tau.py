"""scripts/series_tau.py measures how long a series remembers itself: on AR(1) series, whose
integrated autocorrelation time is known, from a run's log (Z) and from carom analyze's JSON
(psi6)."""

import json
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import SOURCE_DIR

SCRIPT = SOURCE_DIR / "scripts" / "series_tau.py"


def tau_of(*args):
    return subprocess.run([sys.executable, SCRIPT, *map(str, args)], capture_output=True,
                          text=True)


def ar1(a, n, seed):
    """x_k = a x_{k-1} + noise: its integrated autocorrelation time is (1 + a) / (1 - a) steps."""
    rng = np.random.default_rng(seed)
    x = np.empty(n)
    x[0] = rng.normal() / np.sqrt(1 - a * a)
    for k in range(1, n):
        x[k] = a * x[k - 1] + rng.normal()
    return x


def write_log(path, z, interval):
    with open(path, "w") as f:
        f.write("time,Z\n0,\n")  # a log's first row has no interval
        for k, value in enumerate(z, start=1):
            f.write(f"{k * interval!r},{value!r}\n")


def test_tau_of_a_logs_z_and_of_an_analysis_psi6(tmp_path):
    """a = 0.8 remembers itself for 9 rows: 4.5 units at rows half a unit apart, within Sokal's
    error, resolved, and twice that in CPU seconds at 2 a unit; a window of it; psi6 from an
    analysis's JSON alike; a series far shorter than 50 of its times gives a lower bound."""
    log = tmp_path / "log.csv"
    write_log(log, 10.0 + 0.01 * ar1(0.8, 20000, 1), 0.5)
    done = tau_of(log, "--cpu-per-unit", "2")
    assert done.returncode == 0, done.stderr
    tau, error, cpu = map(float, re.search(
        r"tau of Z (\S+) \+- (\S+) units \((\S+) \+- \S+ CPU s\)", done.stdout).groups())
    assert abs(tau - 4.5) < 3 * error and error < 1.0, done.stdout
    assert cpu == pytest.approx(2 * tau, rel=1e-2)
    assert "20000 rows 0.5 apart" in done.stdout
    window = tau_of(log, "--from", "1000", "--to", "6000")
    assert "over (1000, 6000], 10000 rows" in window.stdout, window.stdout

    analysis = tmp_path / "psi6.json"
    psi6 = 0.7 + 0.01 * ar1(0.8, 20000, 2)
    analysis.write_text(json.dumps({"psi6": {"t": [10.0 * k for k in range(len(psi6))],
                                             "global": psi6.tolist()}}))
    found = tau_of(analysis, "--from", "0")
    assert "over [0, 199990], 20000 rows" in found.stdout, found.stdout  # frames at instants
    tau, error = map(float, re.search(r"tau of \|psi6\| (\S+) \+- (\S+) units",
                                      found.stdout).groups())
    assert abs(tau - 90.0) < 3 * error, found.stdout

    write_log(log, 10.0 + 0.01 * ar1(0.99, 300, 3), 0.5)
    short = tau_of(log)
    assert short.returncode == 0 and re.search(r"tau of Z > \S+ units", short.stdout), short.stdout
    assert "CPU s" not in short.stdout


def test_what_it_cannot_measure_is_refused(tmp_path):
    log = tmp_path / "log.csv"
    log.write_text("time,Z\n0,\n1,10\n2,10.1\n4,10.2\n5,10\n")
    uneven = tau_of(log)
    assert uneven.returncode != 0 and "evenly spaced" in uneven.stderr
    assert "fewer than 3" in tau_of(log, "--from", "3").stderr
    log.write_text("time,Z\n0,\n1,1\n2,1\n3,1\n4,1\n")
    assert "no fluctuation" in tau_of(log).stderr
    spheres = tmp_path / "spheres.json"
    spheres.write_text(json.dumps({"psi6": None}))
    assert "no psi6" in tau_of(spheres).stderr
    bad = tau_of(log, "--cpu-per-unit", "0")
    assert bad.returncode == 2 and "--cpu-per-unit" in bad.stderr
