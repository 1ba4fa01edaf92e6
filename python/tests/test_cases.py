"""The classic assignment's reference cases (tests/data/cases, see its README.md) through Python: the expected
files, and the command line's stdout, character for character."""

import re

import numpy as np
import pytest

import carom

TABLE_HEADER = "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n"

# (input, end time, expected file): *.expected hold the table without its header, *.csv the csv.
EXPECTED = [
    ("walls_only.txt", 20, "walls_only.T20.expected"),
    ("particles_only.txt", 18, "particles_only.T18.expected"),
    ("normal.txt", 20, "normal.T20.csv"),
    ("normal.txt", 100, "normal.T100.csv"),
    ("particles1.txt", 15, "particles1.T15.csv"),
    ("particles1.txt", 100, "particles1.T100.csv"),
]
TRACES = [("normal.txt", 20, "normal.T20.trace"), ("particles1.txt", 100, "particles1.T100.trace")]


def read_text(path):
    with open(path, newline="") as f:
        return f.read()


def test_every_case_file_is_covered(cases):
    # A new expected file in tests/data/cases must be added to EXPECTED or TRACES.
    listed = {expected for _, _, expected in EXPECTED + TRACES}
    on_disk = {p.name for p in cases.iterdir() if p.suffix in (".expected", ".csv", ".trace")}
    assert on_disk == listed


@pytest.mark.parametrize("engine", ["fast", "reference"])
@pytest.mark.parametrize("name,end,expected", EXPECTED, ids=[e for _, _, e in EXPECTED])
def test_case_gives_the_expected_file(cases, name, end, expected, engine):
    sim = carom.read(cases / name, engine=engine)
    sim.run(end)
    assert sim.time == end
    if expected.endswith(".csv"):
        assert sim.format("csv") == read_text(cases / expected)
    else:
        assert sim.format("table") == TABLE_HEADER + read_text(cases / expected)


@pytest.mark.parametrize("name,end,expected", EXPECTED, ids=[e for _, _, e in EXPECTED])
def test_case_matches_the_cli_stdout(cli, cases, name, end, expected):
    sim = carom.read(cases / name)
    sim.run(end)
    assert sim.format("table") == cli("run", cases / name, end)
    assert sim.format("csv") == cli("run", cases / name, end, "--format", "csv")


def trace_events(text):
    """[(TIME line, {particle: its line})] of a .trace file: each event and every stored state."""
    events = []
    for line in text.splitlines():
        if line.startswith("TIME = "):
            events.append((line[len("TIME = "):], {}))
        else:
            match = re.match(r"particle (\d+): ", line)
            assert match, line
            events[-1][1][int(match.group(1))] = line
    return events


@pytest.mark.parametrize("name,end,trace", TRACES, ids=[t for _, _, t in TRACES])
def test_collision_log_follows_the_trace(cases, name, end, trace):
    # The trace lists each processed collision's time; the log must have the same collisions at
    # the same times. Running on to each collision's time (in pieces), the particles in the
    # collisions at that instant are where the trace's last block at that instant stores them.
    events = trace_events(read_text(cases / trace))
    log = carom.read(cases / name).run(end, collisions=True)
    assert [f"{t:.6f}" for t in log["time"]] == [t for t, _ in events]

    sim = carom.read(cases / name)
    pieces = []
    for k, (time_text, block) in enumerate(events):
        if k + 1 < len(events) and events[k + 1][0] == time_text:
            continue  # not the last event at this instant
        t = float(log["time"][k])
        pieces.append(sim.run(t, collisions=True))
        table = sim.format("table").splitlines()[1:]
        at_t = log[log["time"] == t]
        involved = set(at_t["i"].tolist()) | {j for j in at_t["j"].tolist() if j >= 0}
        assert involved
        for i in involved:
            assert table[i] == block[i], f"t = {time_text}, particle {i}"
    pieces.append(sim.run(end, collisions=True))
    whole = carom.read(cases / name)
    whole.run(end)
    assert sim.format("table") == whole.format("table")
    assert np.concatenate(pieces).tobytes() == log.tobytes()


def test_examples_are_the_cases(cases, examples):
    # The examples directory holds the same inputs; running them gives the same results.
    for name in ("walls_only.txt", "particles_only.txt", "normal.txt", "particles1.txt"):
        a = carom.read(cases / name)
        b = carom.read(examples / name)
        a.run(30)
        b.run(30)
        assert a.format("table") == b.format("table"), name
