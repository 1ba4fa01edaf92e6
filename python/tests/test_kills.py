"""A run killed hard (SIGKILL: nothing can be saved then) at any moment and resumed from its last
periodic checkpoint, again and again, writes the files of a run never killed, byte for byte: the
event log (every collision exactly once), the time series and the trajectory. Kills land at
random moments (a seeded generator, so a failure can be replayed)."""

import json
import random
import signal
import subprocess
import time

import pytest

END = "200"
OUTPUTS = ["--events", "events.csv", "--log", "series.csv", "--log-every", "0.5",
           "--dump", "frames.xyz", "--every", "2", "--format", "json", "-q"]
FILES = ("events.csv", "series.csv", "frames.xyz")


@pytest.mark.parametrize("dim,seed", [(2, 11), (3, 12)], ids=["disks", "spheres"])
def test_kills_at_random_moments_lose_nothing(cli, tmp_path, dim, seed):
    whole, chain = tmp_path / "whole", tmp_path / "chain"
    for folder in (whole, chain):
        folder.mkdir()
        cli("init", "--dim", str(dim), "--n", "300", "--phi", "0.4", "--seed", str(seed),
            "--boundary", "periodic", "-o", folder / "start.txt")
    cli("run", "start.txt", END, *OUTPUTS, "-o", "result.json", cwd=whole)

    moments = random.Random(seed)
    kills = 0
    checkpoint = chain / "run.ckpt"

    def saved():
        """Which checkpoint is on disk (each save is a new file renamed into place)."""
        if not checkpoint.exists():
            return None
        status = checkpoint.stat()
        return status.st_ino, status.st_mtime_ns

    while True:
        start = ["--resume", "run.ckpt"] if checkpoint.exists() else ["start.txt"]
        before = saved()
        # The result goes to a file: a pipe left unread could hold a finished run up.
        run = subprocess.Popen([cli.exe, "run", *start, END, *OUTPUTS, "-o", "result.json",
                                "--checkpoint", "run.ckpt", "--checkpoint-every", "997"],
                               cwd=chain, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        # Killed at a random moment after it saved a checkpoint of its own (so every piece
        # makes progress), a dozen times; then it runs to the end.
        while kills < 12 and run.poll() is None and saved() == before:
            time.sleep(0.0005)
        time.sleep(moments.uniform(0.0, 0.02))
        if kills < 12 and run.poll() is None:
            run.send_signal(signal.SIGKILL)
            run.communicate(timeout=60)
            kills += 1
            continue
        err = run.communicate(timeout=120)[1]
        assert run.returncode == 0, err.decode()
        break
    assert kills >= 6, f"only {kills} kills: the runs ended before they could be killed"
    assert without_clock(chain / "result.json") == without_clock(whole / "result.json")
    for name in FILES:
        assert (chain / name).read_bytes() == (whole / name).read_bytes(), \
            f"{name} differs after {kills} kills"


def without_clock(path):
    summary = json.loads(path.read_text())
    for key in ("wall_seconds", "events_per_second", "compressibility_factor_drift"):
        del summary[key]
    return summary
