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
    assert result["msd"]["msd"][0] == 0 and result["rdf"]["contact"]["Z"] > 1
    structure, self_scattering = result["structure_factor"], result["self_scattering"]
    assert structure["s"].dtype == np.float64 and len(structure["k"]) == len(structure["s"])
    assert np.array_equal(self_scattering["t"], result["msd"]["t"])
    assert self_scattering["fs"][0] == pytest.approx(1, abs=1e-14)
    assert np.isnan(self_scattering["alpha2"][0]) and self_scattering["tau_alpha"] > 0


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
