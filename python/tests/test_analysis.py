"""carom.analyze: the command line's `carom analyze`, bit for bit, with numpy arrays."""

import json

import numpy as np
import pytest

import carom


def equal(python, cli):
    """The Python result against the CLI's JSON: the same keys and the same numbers, bit for bit."""
    if isinstance(cli, dict):
        assert set(python) == set(cli)
        return all(equal(python[key], cli[key]) for key in cli)
    if isinstance(python, np.ndarray):
        return np.array_equal(python.ravel(), np.array(cli, dtype=np.float64).ravel())
    return python == cli


@pytest.fixture(params=[(2, "gsd"), (2, "xyz"), (3, "gsd")], ids=["2d-gsd", "2d-xyz", "3d-gsd"])
def trajectory(request, cli, tmp_path):
    dim, ending = request.param
    start, path = tmp_path / "start.txt", tmp_path / f"run.{ending}"
    cli("init", "--dim", dim, "--n", 300, "--phi", 0.3, "--boundary", "periodic", "-o", start)
    cli("run", start, 6, "--rule", "elastic", "--boundary", "periodic", "--dump", path,
        "--every", 0.5, "--log", tmp_path / "run.csv", "--log-every", 0.5, "-o", tmp_path / "e.txt")
    return dim, path, tmp_path / "run.csv"


def test_analyze_equals_cli_analyze(cli, tmp_path, trajectory):
    dim, path, log = trajectory
    options = ["--equilibrate", 1, "--log", log, "--bin", 0.025, "--r-max", 3]
    cli("analyze", path, *options, "-o", tmp_path / "cli.json", "--html", tmp_path / "cli.html")
    result = carom.analyze(path, equilibrate=1, log=log, bin=0.025, r_max=3,
                           html=tmp_path / "py.html")
    with open(tmp_path / "cli.json") as f:
        assert equal(result, json.load(f))
    assert (tmp_path / "py.html").read_bytes() == (tmp_path / "cli.html").read_bytes()
    # numpy arrays, shaped
    n = result["particles"]
    assert result["snapshot"]["position"].shape == (n, dim)
    assert result["rdf"]["g"].dtype == np.float64 and len(result["rdf"]["r"]) == 120
    assert result["time"][0] >= 1
    assert (result["psi6"] is None) == (dim == 3)
    assert result["msd"]["msd"][0] == 0 and result["rdf"]["contact"]["Z"] > 1


def test_analyze_refuses_what_it_cannot_do(tmp_path, trajectory):
    _, path, _ = trajectory
    with pytest.raises(carom.InputError, match="missing.gsd"):
        carom.analyze(tmp_path / "missing.gsd")
    with pytest.raises(ValueError, match="bin must be greater than 0"):
        carom.analyze(path, bin=-1)
    with pytest.raises(ValueError, match="no frame at or after t = 100"):
        carom.analyze(path, equilibrate=100)
    with pytest.raises(ValueError, match="g\\(r\\) reaches"):
        carom.analyze(path, r_max=1000)
    with pytest.raises(ValueError, match="equilibrate must be a number"):
        carom.analyze(path, equilibrate="soon")


def test_analyze_refuses_a_page_that_is_one_of_its_inputs(tmp_path, trajectory):
    """Regression: html=the trajectory (or the log) overwrote it with the page."""
    _, path, log = trajectory
    (tmp_path / "sub").mkdir()
    before = path.read_bytes(), log.read_bytes()
    for html in (path, tmp_path / "sub" / ".." / path.name, log):
        with pytest.raises(ValueError, match="name the same file"):
            carom.analyze(path, log=log, html=html)
    assert (path.read_bytes(), log.read_bytes()) == before
