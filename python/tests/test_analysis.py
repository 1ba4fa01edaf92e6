"""carom.analyze: the command line's `carom analyze`, bit for bit, with numpy arrays."""

import json

import gsd.hoomd
import numpy as np
import pytest

import carom
from _bond_order_reference import bond_order


def equal(python, cli):
    """The Python result against the CLI's JSON: the same keys and the same numbers, bit for bit."""
    if isinstance(cli, dict):
        assert set(python) == set(cli)
        return all(equal(python[key], cli[key]) for key in cli)
    if isinstance(python, list) and isinstance(cli, list):  # cluster_sizes: an array a frame
        return len(python) == len(cli) and all(equal(p, c) for p, c in zip(python, cli))
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
    assert (result["steinhardt"] is None) == (dim == 2)
    if dim == 3:
        order = result["steinhardt"]
        assert order["q6"].dtype == np.float64 and order["solid_like"].dtype == np.int64
        assert np.array_equal(order["t"], result["time"])
        assert order["last_frame"]["solid_like"].dtype == bool
        assert order["last_frame"]["w6_bar"].shape == (n,)
    assert result["msd"]["msd"][0] == 0 and result["rdf"]["contact"]["Z"] > 1


def test_analyze_refuses_what_it_cannot_do(tmp_path, trajectory):
    _, path, _ = trajectory
    with pytest.raises(carom.InputError, match="missing.gsd"):
        carom.analyze(tmp_path / "missing.gsd")
    with pytest.raises(ValueError, match="bin must be greater than 0"):
        carom.analyze(path, bin=-1)
    with pytest.raises(ValueError, match="order_cutoff must be greater than 0"):
        carom.analyze(path, order_cutoff=0)
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


# ---- The Steinhardt bond order against numpy's own (_bond_order_reference.py) -------------------

def write_gsd(path, frames, box):
    """Frames of spheres of diameter 1 in a periodic cube, as HOOMD writes them (centred, in
    float32); returns them as carom reads them back, with the box's side."""
    with gsd.hoomd.open(str(path), "wb") as f:
        for step, position in enumerate(frames):
            frame = gsd.hoomd.Snapshot()
            frame.configuration.step = step
            frame.configuration.dimensions = 3
            frame.configuration.box = [box, box, box, 0, 0, 0]
            frame.particles.N = len(position)
            frame.particles.position = np.asarray(position, dtype=np.float32) - box / 2
            frame.particles.diameter = np.ones(len(position), dtype=np.float32)
            f.append(frame)
    with gsd.hoomd.open(str(path), "rb") as f:
        side = float(f[0].configuration.box[0])
        return [frame.particles.position.astype(np.float64) + 0.5 * side for frame in f], side


def fcc_lattice(cells, spacing):
    a = spacing * np.sqrt(2)
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    corners = np.array([[i, j, k] for i in range(cells) for j in range(cells)
                        for k in range(cells)], dtype=float)
    return ((corners[:, None, :] + basis[None, :, :]).reshape(-1, 3) * a), cells * a


INVARIANTS = [f"{kind}{l}{bar}" for l in (4, 6) for kind in "qw" for bar in ("", "_bar")]


def check_against_numpy(result, frames, box, cutoff):
    order = result["steinhardt"]
    assert order["cutoff"] == cutoff
    for f, position in enumerate(frames):
        expected = bond_order(position, [box] * 3, True, cutoff)
        for key in INVARIANTS:
            assert abs(order[key][f] - expected[key].mean()) < 1e-12, (f, key)
        assert order["solid_like"][f] == expected["solid_like"].sum()
        assert np.array_equal(order["cluster_sizes"][f], expected["cluster_sizes"])
        assert order["largest_cluster"][f] == max(expected["cluster_sizes"], default=0)
    last = order["last_frame"]
    for key in INVARIANTS:
        np.testing.assert_allclose(last[key], expected[key], rtol=0, atol=1e-12, err_msg=key)
    for key in ("neighbours", "solid_bonds", "solid_like", "cluster"):
        assert np.array_equal(last[key], expected[key]), key
    return expected


@pytest.mark.parametrize("cutoff", [None, 1.3])
def test_bond_order_of_an_ideal_gas_is_numpys(tmp_path, cutoff):
    """Random points (about 12 within 1.5 d): bonds in every direction, no crystal."""
    rng = np.random.default_rng(4)
    box = 7.0
    frames, box = write_gsd(tmp_path / "gas.gsd", [rng.uniform(0, box, (350, 3)) for _ in range(3)],
                            box)
    result = carom.analyze(tmp_path / "gas.gsd", order_cutoff=cutoff)
    expected = check_against_numpy(result, frames, box, cutoff or 1.5)
    assert expected["solid_like"].sum() <= 3


def test_bond_order_of_crystals_is_numpys(tmp_path):
    """An FCC crystal at the melting density (nearest 1.107 d), the same shaken, and the same
    melted but for two balls of crystal: the literature's FCC values, then one cluster of every
    particle, then two clusters and a liquid around them."""
    rng = np.random.default_rng(9)
    lattice, box = fcc_lattice(7, (np.pi / (3 * np.sqrt(2) * 0.545)) ** (1 / 3))
    shaken = (lattice + rng.normal(0, 0.06, lattice.shape)) % box
    centres, radii = np.array([[0.25], [0.75]]) * box, np.array([[3.2], [2.5]])

    def in_crystallite(x, skin):
        r = x[None, :, :] - centres[:, None, :]
        return (np.linalg.norm(r - box * np.rint(r / box), axis=2) < radii + skin).any(axis=0)

    melted = shaken.copy()
    liquid = ~in_crystallite(melted, 0.0)
    melted[liquid] = rng.uniform(0, box, (liquid.sum(), 3))
    # The liquid kept out of the crystallites and a skin of half a diameter around them.
    while (inside := liquid & in_crystallite(melted, 0.5)).any():
        melted[inside] = rng.uniform(0, box, (inside.sum(), 3))
    frames, box = write_gsd(tmp_path / "fcc.gsd", [lattice, shaken, melted], box)
    result = carom.analyze(tmp_path / "fcc.gsd")
    order = result["steinhardt"]
    assert abs(order["q4"][0] - 0.19094) < 1e-5 and abs(order["q6"][0] - 0.57452) < 1e-5
    assert abs(order["w6"][0] + 0.01316) < 1e-5
    assert order["largest_cluster"][0] == len(lattice) == order["solid_like"][1]
    expected = check_against_numpy(result, frames, box, 1.5)
    sizes = expected["cluster_sizes"]
    assert len(sizes) >= 2 and sizes[0] > sizes[1] > 10, sizes
