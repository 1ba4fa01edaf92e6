"""scripts/log_window.py measures a window of a run's log as the run's summary measures its own
window: the mean of the rows' interval Z is the window's Z."""

import json
import re
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR

SCRIPT = SOURCE_DIR / "scripts" / "log_window.py"


def window(*args):
    return subprocess.run([sys.executable, SCRIPT, *map(str, args)], capture_output=True,
                          text=True)


def test_a_logs_window_is_the_summarys_measurement(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "300", "--phi", "0.6", "--seed", "4", "--boundary", "periodic", "-o", start)
    log, summary = tmp_path / "log.csv", tmp_path / "summary.json"
    cli("run", start, "12", "--equilibrate", "4", "--sampler", "ecmc", "--log", log,
        "--log-every", "0.25", "--summary", summary, "-q", "-o", tmp_path / "end.txt")
    z = json.loads(summary.read_text())["compressibility_factor"]
    done = window(log, "--phi", "0.6", "--from", "4", "--to", "12", "--blocks", "4")
    assert done.returncode == 0, done.stderr
    measured, error = map(float, re.search(r"Z (\S+) \+- ([^,]+),", done.stdout).groups())
    assert measured == pytest.approx(z, rel=1e-5)  # the five digits printed
    assert 0.0 < error < 0.1 * z
    # The window's pressure tensor, the run's own (from the chains' running sums, as the
    # summary takes it: the means of the rows' would weigh each axis's chains unequally), to the
    # four decimals printed.
    tensor = json.loads(summary.read_text())["pressure_tensor"]
    stress = re.search(r"pxx (\S+) pyy (\S+) pxy (\S+)", done.stdout)
    assert stress, done.stdout
    for printed, key in zip(map(float, stress.groups()), ("xx", "yy", "xy")):
        assert printed == pytest.approx(tensor[key], abs=6e-5)
    # Two logs: each, and their mean.
    both = window(log, log, "--phi", "0.6", "--from", "4", "--to", "12")
    assert both.returncode == 0 and "mean of 2" in both.stdout
    # A window with too few rows for its blocks is refused by name.
    short = window(log, "--phi", "0.6", "--from", "11", "--to", "12", "--blocks", "6")
    assert short.returncode != 0 and "fewer than two a block" in short.stderr
    # One block gives no error: refused as bad input (exit 2), not a traceback.
    one = window(log, "--phi", "0.6", "--from", "4", "--to", "12", "--blocks", "1")
    assert one.returncode == 2 and "--blocks must be 2 or more" in one.stderr
