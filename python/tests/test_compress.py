"""carom.compress: the command line's `carom compress`, bit for bit, and packings checked for
overlaps independently (numpy, every pair by minimum image)."""

import json

import numpy as np
import pytest

import carom


def overlaps(sim):
    """The largest overlap of any pair, relative to its contact distance (negative: none)."""
    x, r, box = sim.positions, sim.radii, sim.box
    i, j = np.triu_indices(sim.n, 1)
    delta = x[i] - x[j]
    if sim.boundary == "periodic":
        delta -= box * np.rint(delta / box)
    distance = np.sqrt(np.sum(delta ** 2, axis=1))
    contact = r[i] + r[j]
    return np.max((contact - distance) / contact)


def outside_walls(sim):
    """How far any particle reaches through a wall (negative: none)."""
    if sim.boundary == "periodic":
        return -1.0
    x, r = sim.positions, sim.radii[:, None]
    return max(np.max(r - x), np.max(x + r - sim.box))


CASES = {
    "2d-periodic-poly-phi": (dict(n=200, phi=0.3, polydispersity=0.1, boundary="periodic"),
                             dict(phi=0.78)),
    "2d-walls-jam": (dict(n=120, phi=0.3, polydispersity=0.2, boundary="walls"),
                     dict(jam=True, rate=0.1)),
    "3d-periodic-jam": (dict(dim=3, n=100, phi=0.3, boundary="periodic"), dict(jam=True, rate=0.1)),
    "3d-walls-phi": (dict(dim=3, n=150, phi=0.2, boundary="walls"), dict(phi=0.5)),
}


@pytest.mark.parametrize("init,options", CASES.values(), ids=CASES.keys())
def test_compress_equals_cli_compress_and_overlaps_nothing(cli, tmp_path, init, options):
    sim = carom.init(rule="elastic", **init)
    dense, summary = carom.compress(sim, **options)
    assert sim.time == 0 and dense.time == 0 and dense.n == sim.n
    if "phi" in options:
        assert summary["status"] == "reached_target"
        assert abs(summary["packing_fraction"] - options["phi"]) < 1e-13
    else:
        assert summary["status"] == "jammed" and summary["compressibility_factor"] > 1e12
    # No overlap, checked without carom; size ratios kept.
    assert overlaps(dense) < 1e-12
    assert outside_walls(dense) < 1e-12
    ratio = dense.radii / sim.radii
    assert np.allclose(ratio, ratio[0], rtol=1e-13)
    # The command line gives the same packing, bit for bit.
    start, out = tmp_path / "start.txt", tmp_path / "out.txt"
    args = ["--dim", init.get("dim", 2), "--n", init["n"], "--phi", init["phi"],
            "--polydispersity", init.get("polydispersity", 0),
            "--boundary", init.get("boundary", "walls")]
    cli("init", *args, "-o", start)
    flags = (["--phi", options["phi"]] if "phi" in options else ["--jam"]) + \
        ["--rate", options.get("rate", 0.01)]
    cli("compress", start, *flags, "--boundary", init.get("boundary", "walls"), "-o", out,
        "--summary", tmp_path / "summary.json", "-q")
    # The same summary, key for key (the start's name and the clock aside).
    from_cli_summary = json.loads((tmp_path / "summary.json").read_text())
    assert list(summary) == list(from_cli_summary)
    for key in ("input", "wall_seconds"):
        del summary[key], from_cli_summary[key]
    assert summary == from_cli_summary
    from_cli = carom.read(out, boundary=init.get("boundary", "walls"))
    assert np.array_equal(from_cli.positions, dense.positions)
    assert np.array_equal(from_cli.radii, dense.radii)
    assert np.array_equal(from_cli.velocities, dense.velocities)
    # It runs on.
    dense.run(0.5)
    assert dense.events > 0


def test_compress_refuses_what_cannot_be_done():
    sim = carom.init(n=100, phi=0.3, boundary="periodic")
    with pytest.raises(ValueError, match="close packing"):
        carom.compress(sim, phi=0.95)
    with pytest.raises(ValueError, match="phi .* or jam=True"):
        carom.compress(sim)
    with pytest.raises(ValueError, match="phi .* or jam=True"):
        carom.compress(sim, phi=0.5, jam=True)
    with pytest.raises(ValueError, match="growth rate"):
        carom.compress(sim, jam=True, rate=0)


@pytest.mark.parametrize("dim,boundary", [(2, "periodic"), (3, "walls")])
def test_unit_diameter_rescales_the_packing_as_the_cli_does(cli, tmp_path, dim, boundary):
    sim = carom.init(n=120, phi=0.3, dim=dim, boundary=boundary, polydispersity=0.1)
    grown, summary = carom.compress(sim, phi=0.5)
    unit, unit_summary = carom.compress(sim, phi=0.5, unit_diameter=True)
    assert summary["mean_diameter"] > 1.1 and not summary["unit_diameter"]
    assert abs(unit_summary["mean_diameter"] - 1.0) < 1e-14 and unit_summary["unit_diameter"]
    assert abs(np.mean(2 * unit.radii) - 1.0) < 1e-14
    factor = 1.0 / summary["mean_diameter"]
    assert np.array_equal(unit.box, grown.box * factor)
    assert np.array_equal(unit.positions, grown.positions * factor)
    assert np.array_equal(unit.velocities, grown.velocities)
    assert unit.observables()["packing_fraction"] == pytest.approx(0.5, rel=1e-13)
    assert overlaps(unit) < 1e-12 and outside_walls(unit) < 1e-12
    unit.run(0.5)
    assert unit.events > 0
    start, out = tmp_path / "start.txt", tmp_path / "out.txt"
    cli("init", "--dim", dim, "--n", 120, "--phi", 0.3, "--polydispersity", 0.1,
        "--boundary", boundary, "-o", start)
    cli("compress", start, "--phi", 0.5, "--unit-diameter", "-o", out)
    from_cli = carom.read(out)
    assert np.array_equal(from_cli.positions, carom.compress(sim, phi=0.5,
                                                              unit_diameter=True)[0].positions)
    assert from_cli.boundary == boundary and from_cli.rule == "elastic"
