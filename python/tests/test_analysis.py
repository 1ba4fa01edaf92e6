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
        # alpha2 is NaN (null in JSON) at t = 0
        return np.array_equal(python.ravel(), np.array(cli, dtype=np.float64).ravel(),
                              equal_nan=True)
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
    if dim == 2:
        orientation = result["psi6"]["orientation"]
        assert orientation.dtype == np.float64 and orientation.shape == result["time"].shape
        assert np.all((orientation > -30) & (orientation <= 30))
    assert (result["steinhardt"] is None) == (dim == 2)
    if dim == 3:
        order = result["steinhardt"]
        assert order["q6"].dtype == np.float64 and order["solid_like"].dtype == np.int64
        assert np.array_equal(order["t"], result["time"])
        assert order["last_frame"]["solid_like"].dtype == bool
        assert order["last_frame"]["w6_bar"].shape == (n,)
    assert result["msd"]["msd"][0] == 0 and result["rdf"]["contact"]["Z"] > 1
    structure, self_scattering = result["structure_factor"], result["self_scattering"]
    assert structure["s"].dtype == np.float64 and len(structure["k"]) == len(structure["s"])
    assert np.array_equal(self_scattering["t"], result["msd"]["t"])
    assert self_scattering["fs"][0] == pytest.approx(1, abs=1e-14)
    assert np.isnan(self_scattering["alpha2"][0]) and self_scattering["tau_alpha"] > 0


ANALYSES = ("rdf", "msd", "psi6", "steinhardt", "structure_factor", "self_scattering")


def test_only_some_analyses_as_the_command_line_computes_them(cli, tmp_path, trajectory):
    """only= computes the analyses named (the rest None), the numbers of the whole analysis, and
    the command line's --only gives the same JSON; self_scattering without what it needs, or a
    name that is no analysis, is refused by both."""
    dim, path, _ = trajectory
    whole = carom.analyze(path)
    for only in ("psi6", ["rdf", "structure_factor"],
                 ("msd", "self_scattering", "structure_factor"), "psi6, rdf"):
        names = only.replace(" ", "").split(",") if isinstance(only, str) else list(only)
        cli("analyze", path, "--only", ",".join(names), "-o", tmp_path / "cli.json")
        result = carom.analyze(path, only=only)
        with open(tmp_path / "cli.json") as f:
            assert equal(result, json.load(f))
        for name in ANALYSES:
            applies = whole[name] is not None
            assert (result[name] is not None) == (applies and name in names), (only, name)
            if result[name] is not None:
                assert equal(result[name], json.loads(json.dumps(whole[name], default=list)))
    for bad, words in (("sk", "'sk' is not an analysis"), ("psi6,", "'' is not an analysis"),
                       ("", "'' is not an analysis"), ("psi6,psi6", "'psi6' is named twice"),
                       ("self_scattering,msd", "self_scattering needs structure_factor too")):
        assert words in cli.error("analyze", path, "--only", bad)
        with pytest.raises(ValueError, match=words):
            carom.analyze(path, only=bad)
    # An option of an analysis left out would do nothing: refused by both.
    assert "fs_k (--fs-k) is an option of self_scattering" in cli.error(
        "analyze", path, "--only", "psi6", "--fs-k", "4")
    with pytest.raises(ValueError, match="r_max \\(--r-max\\) is an option of rdf"):
        carom.analyze(path, only="psi6", r_max=2)
    with pytest.raises(ValueError, match="only must name analyses"):
        carom.analyze(path, only=["psi6,rdf"])
    with pytest.raises(ValueError, match="self_scattering needs msd too"):
        carom.analyze(path, only="self_scattering", fs_k=6)
    with pytest.raises(ValueError, match="only must name analyses"):
        carom.analyze(path, only=[])


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


# ---- S(k), F_s(k,t) and alpha2(t) against numpy --------------------------------------------------

CAP = 100  # k-vectors a shell at most (kWaveVectorsPerShell)


def write_random_frames(path, box, frames, n, seed):
    """A GSD trajectory of `n` random points (float32, as GSD holds them) with random image flags,
    frames 0.25 apart; returns their positions and image flags as float64."""
    import gsd.hoomd
    dim, rng = len(box), np.random.default_rng(seed)
    positions, images = [], []
    with gsd.hoomd.open(str(path), "wb") as trajectory:
        for f in range(frames):
            snapshot = gsd.hoomd.Snapshot()
            snapshot.configuration.box = [*box, *([1.0] if dim == 2 else []), 0, 0, 0]
            snapshot.configuration.dimensions = dim
            snapshot.configuration.step = f
            snapshot.particles.N = n
            position = np.zeros((n, 3), dtype=np.float32)
            position[:, :dim] = (rng.random((n, dim)) - 0.5) * np.array(box)
            image = np.zeros((n, 3), dtype=np.int32)
            image[:, :dim] = rng.integers(-2, 3, (n, dim))
            snapshot.particles.position = position
            snapshot.particles.image = image
            snapshot.particles.diameter = np.ones(n, dtype=np.float32)
            snapshot.log["time"] = np.array([0.25 * f])
            trajectory.append(snapshot)
            positions.append(position[:, :dim].astype(np.float64))
            images.append(image[:, :dim].astype(np.float64))
    return np.array(positions), np.array(images)


def grid_shells(box, shells):
    """The k-vectors carom keeps in shells 1..shells of the box's grid: n in lexicographic order,
    one of n and -n, |k| in [(m - 1/2), (m + 1/2)) 2 pi / L_min, at most CAP a shell, those at
    floor(j count / CAP)."""
    box = np.array(box, dtype=np.float64)
    ratio = box.min() / box
    reach = np.ceil((shells + 0.5) / ratio).astype(int)
    n = np.stack(np.meshgrid(*[np.arange(-r, r + 1) for r in reach], indexing="ij"),
                 axis=-1).reshape(-1, len(box))
    first_nonzero = n[np.arange(len(n)), np.argmax(n != 0, axis=1)]
    n = n[first_nonzero > 0]
    m = np.floor(np.sqrt(((n * ratio) ** 2).sum(axis=1)) + 0.5)
    chosen = []
    for shell in range(1, shells + 1):
        members = n[m == shell]
        if len(members) > CAP:
            members = members[(np.arange(CAP) * len(members)) // CAP]
        chosen.append(members)
    return chosen


@pytest.mark.parametrize("box", [(8.3, 9.1), (6.5, 7.1, 7.7)], ids=["2d", "3d"])
def test_scattering_against_numpy(tmp_path, box):
    positions, images = write_random_frames(tmp_path / "random.gsd", box, 6, 60, seed=len(box))
    result = carom.analyze(tmp_path / "random.gsd")
    dim, L = len(box), np.array(box, dtype=np.float32).astype(np.float64)  # as GSD holds it
    step = 2 * np.pi / L.min()
    shells = grid_shells(L, int(np.floor(20.0 / step * (1 + 1e-12))))
    wave = [2 * np.pi * members / L for members in shells]

    # S(k) = |sum_j exp(-i k.r_j)|^2 / N, over the frames and the shell's vectors
    s = np.array([np.mean([np.abs(np.exp(-1j * (x @ k.T)).sum(axis=0)) ** 2 / len(x)
                           for x in positions]) for k in wave])
    k_shell = np.array([np.linalg.norm(k, axis=1).mean() for k in wave])
    sk = result["structure_factor"]
    np.testing.assert_allclose(sk["s"], s, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(sk["k"], k_shell, rtol=1e-12)
    peak = int(np.argmax(s))
    assert sk["k_peak"] == pytest.approx(k_shell[peak], rel=1e-12)

    # F_s(k,t) at the peak's shell, and alpha2, over every time origin
    unwrapped = positions + images * L
    k = wave[peak]
    fs, alpha2 = [], []
    for lag in range(len(unwrapped)):
        dr = unwrapped[lag:] - unwrapped[:len(unwrapped) - lag]
        fs.append(np.mean(np.cos(dr @ k.T)))
        r2 = (dr ** 2).sum(axis=2)
        alpha2.append(dim * np.mean(r2 ** 2) / ((dim + 2) * np.mean(r2) ** 2) - 1 if lag else
                      np.nan)
    self_scattering = result["self_scattering"]
    assert self_scattering["k"] == pytest.approx(k_shell[peak], rel=1e-12)
    np.testing.assert_allclose(self_scattering["t"], 0.25 * np.arange(len(unwrapped)), rtol=1e-12)
    np.testing.assert_allclose(self_scattering["fs"], fs, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(self_scattering["alpha2"], alpha2, rtol=1e-12, atol=1e-12)
    below = np.nonzero(np.array(fs) < np.exp(-1))[0]
    if len(below):
        i, t = below[0], self_scattering["t"]
        tau = t[i - 1] + (np.exp(-1) - fs[i - 1]) * (t[i] - t[i - 1]) / (fs[i] - fs[i - 1])
        assert self_scattering["tau_alpha"] == pytest.approx(tau, rel=1e-12)
    else:
        assert self_scattering["tau_alpha"] is None

    # --fs-k picks another shell: the one that holds it
    other = carom.analyze(tmp_path / "random.gsd", fs_k=3 * step + 0.2, k_max=5 * step)
    assert len(other["structure_factor"]["k"]) == 5
    np.testing.assert_allclose(other["structure_factor"]["s"], s[:5], rtol=1e-12, atol=1e-12)
    assert other["self_scattering"]["k"] == pytest.approx(k_shell[2], rel=1e-12)
    expected = [np.mean(np.cos((unwrapped[lag:] - unwrapped[:len(unwrapped) - lag]) @ wave[2].T))
                for lag in range(len(unwrapped))]
    np.testing.assert_allclose(other["self_scattering"]["fs"], expected, rtol=1e-12, atol=1e-12)


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
