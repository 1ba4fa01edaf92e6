"""Mixtures: `carom init --species` and carom.init(species=...) give the same start, bit for
bit; the types survive start files, compression, GSD (read by carom and by gsd.hoomd), extended
XYZ (read by ASE) and LAMMPS dumps; `carom analyze` gives the partial g_ab(r) of a dense binary
mixture, checked against numpy."""

import json

import numpy as np
import pytest

import carom
from _support import assert_bitwise_equal

BINARY = "A:0.5:1.0,B:0.5:1.4"


def types_of(path):
    """The type names and each particle's type index of a start file carom wrote."""
    lines = open(path).read().splitlines()
    record = lines[0].split()
    names = [s[len("types="):].split(",") for s in record if s.startswith("types=")]
    data = [line.split() for line in lines if line and not line.startswith("#")]
    return (names[0] if names else ["A"]), np.array([int(row[-1]) for row in data[3:]])


def test_init_species_counts_diameters_and_bytes(cli, tmp_path):
    a = tmp_path / "a.txt"
    b = tmp_path / "b.txt"
    args = ["init", "--n", "101", "--phi", "0.3", "--species", "A:0.3:1,B:0.3:1.2,C:0.4:1.4",
            "--boundary", "periodic", "--seed", "5"]
    cli(*args, "-o", a)
    cli(*args, "-o", b)
    assert a.read_bytes() == b.read_bytes()
    names, types = types_of(a)
    assert names == ["A", "B", "C"]
    # 30.3, 30.3, 40.4: the largest remainders go to A and B in order.
    assert np.bincount(types).tolist() == [30, 30, 41]
    sim = carom.read(a)
    assert sim.types == ["A", "B", "C"]
    assert_bitwise_equal(sim.typeid, types.astype(np.uint32), "typeid")
    assert np.array_equal(2 * sim.radii, np.array([1.0, 1.2, 1.4])[types])
    # Another seed shuffles the types otherwise.
    cli(*args[:-1], "6", "-o", b)
    assert not np.array_equal(types_of(b)[1], types)


@pytest.mark.parametrize("species", [BINARY, [("A", 0.5, 1.0), ("B", 0.5, 1.4)]])
@pytest.mark.parametrize("dim", [2, 3])
def test_init_species_equals_cli(cli, tmp_path, species, dim):
    path = tmp_path / "start.txt"
    cli("init", "--dim", dim, "--n", 120, "--phi", 0.25, "--species", BINARY, "--seed", 3,
        "-o", path)
    sim = carom.init(n=120, phi=0.25, species=species, seed=3, dim=dim)
    read = carom.read(path)
    assert sim.types == read.types == ["A", "B"]
    for name in ("positions", "velocities", "radii", "masses", "box", "typeid"):
        assert_bitwise_equal(getattr(sim, name), getattr(read, name), name)
    assert np.bincount(sim.typeid).tolist() == [60, 60]


def test_species_excludes_polydispersity_and_radius(cli, tmp_path):
    for extra in (["--polydispersity", "0.1"], ["--radius", "0.7"]):
        message = cli.error("init", "--n", 10, "--phi", 0.2, "--species", BINARY, *extra)
        assert "--species" in message
    message = cli.error("init", "--n", 10, "--phi", 0.2, "--species", "A:0.5:1,B:0.4:1.4")
    assert "sum to 0.9" in message
    with pytest.raises(ValueError, match="species"):
        carom.init(n=10, phi=0.2, species=BINARY, polydispersity=0.1)
    with pytest.raises(ValueError, match="sum to"):
        carom.init(n=10, phi=0.2, species="A:0.5:1,B:0.4:1.4")


@pytest.fixture(scope="module")
def dense_binary(tmp_path_factory):
    """A 50:50 1.0/1.4 disk mixture placed at random at 0.3, compressed to 0.80, run and dumped
    to GSD, XYZ and a LAMMPS dump: (folder, the compressed start's path)."""
    import os
    import subprocess
    folder = tmp_path_factory.mktemp("binary")
    exe = os.environ["CAROM_EXE"]

    def run(*args):
        subprocess.run([exe, *[str(a) for a in args]], check=True, capture_output=True, cwd=folder)

    run("init", "--n", 400, "--phi", 0.3, "--species", BINARY, "--boundary", "periodic",
        "--seed", 2, "-o", "gas.txt")
    run("compress", "gas.txt", "--phi", 0.8, "-o", "dense.txt", "-q")
    for dump in ("run.gsd", "run.xyz", "run.lammpstrj"):
        run("run", "dense.txt", 2, "--dump", dump, "--every", 0.5)
    return folder


def test_compression_keeps_the_types(dense_binary):
    names, types = types_of(dense_binary / "gas.txt")
    dense_names, dense_types = types_of(dense_binary / "dense.txt")
    assert dense_names == names == ["A", "B"]
    assert np.array_equal(types, dense_types)
    dense = carom.read(dense_binary / "dense.txt")
    radii = dense.radii
    assert np.allclose(radii[dense.typeid == 1] / radii[dense.typeid == 0].mean(), 1.4)
    area = np.pi * np.sum(radii ** 2) / np.prod(dense.box)
    assert abs(area - 0.8) < 1e-9


def test_gsd_is_read_with_its_types_by_gsd_hoomd_and_carom(dense_binary):
    gsd_hoomd = pytest.importorskip("gsd.hoomd")
    _, types = types_of(dense_binary / "dense.txt")
    with gsd_hoomd.open(str(dense_binary / "run.gsd"), "rb") as trajectory:
        assert len(trajectory) == 5
        for frame in trajectory:
            assert list(frame.particles.types) == ["A", "B"]
            assert np.array_equal(frame.particles.typeid, types)
            d = frame.particles.diameter
            assert np.allclose(d[types == 1] / d[types == 0], 1.4, rtol=1e-6)
    # And as a start: the last frame.
    start = carom.read(str(dense_binary / "run.gsd"))
    assert start.types == ["A", "B"]
    assert np.array_equal(start.typeid, types)


def test_xyz_species_are_read_by_ase_and_lammps_has_the_types(dense_binary):
    ase_io = pytest.importorskip("ase.io")
    _, types = types_of(dense_binary / "dense.txt")
    frames = ase_io.read(str(dense_binary / "run.xyz"), index=":")
    assert len(frames) == 5
    for atoms in frames:
        assert atoms.get_chemical_symbols() == [["H", "He"][t] for t in types]
        assert list(atoms.arrays["type"]) == [["A", "B"][t] for t in types]
    lines = open(dense_binary / "run.lammpstrj").read().splitlines()
    atoms = lines.index("ITEM: ATOMS id type x y z vx vy vz radius mass ix iy iz")
    rows = [line.split() for line in lines[atoms + 1: atoms + 401]]
    assert [int(r[1]) for r in rows] == (types + 1).tolist()
    # ASE's LAMMPS reader takes the type as the atomic number (ids sorted: carom's order).
    dumped = ase_io.read(str(dense_binary / "run.lammpstrj"), index=":", format="lammps-dump-text")
    assert len(dumped) == 5
    assert all(np.array_equal(atoms.numbers, types + 1) for atoms in dumped)


def direct_partials(frames, edges, periodic_box, types):
    """g(r) and each g_ab(r) by brute force over all pairs (minimum image), as carom defines them:
    pair counts over N_a (N_a - 1) / 2 (a = b) or N_a N_b pairs times the ideal shell share."""
    n = len(types)
    area = np.prod(periodic_box)
    shell = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2) / area
    total = np.zeros(len(edges) - 1)
    partial = {}
    i, j = np.triu_indices(n, 1)
    for positions in frames:
        d = positions[i] - positions[j]
        d -= periodic_box * np.round(d / periodic_box)
        r = np.hypot(d[:, 0], d[:, 1])
        total += np.histogram(r, edges)[0]
        for a in range(2):
            for b in range(a, 2):
                key = "AB"[a] + "-" + "AB"[b]
                pick = ((types[i] == a) & (types[j] == b)) | ((types[i] == b) & (types[j] == a))
                partial[key] = partial.get(key, 0) + np.histogram(r[pick], edges)[0]
    count = np.bincount(types)
    g = total / (len(frames) * n * (n - 1) / 2 * shell)
    pairs = {"A-A": count[0] * (count[0] - 1) / 2, "A-B": count[0] * count[1],
             "B-B": count[1] * (count[1] - 1) / 2}
    return g, {k: partial[k] / (len(frames) * pairs[k] * shell) for k in partial}, pairs


def test_analyze_gives_partials_that_add_up_to_the_total(dense_binary, cli):
    gsd_hoomd = pytest.importorskip("gsd.hoomd")
    result = carom.analyze(str(dense_binary / "run.gsd"))
    rdf = result["rdf"]
    assert sorted(rdf["partial"]) == ["A-A", "A-B", "B-B"]
    for values in rdf["partial"].values():
        assert isinstance(values, np.ndarray) and values.shape == rdf["g"].shape
    weights = rdf["partial_weights"]
    n = 400
    na = nb = 200
    assert weights["A-A"] == pytest.approx(na * (na - 1) / (n * (n - 1)), rel=1e-15)
    assert weights["A-B"] == pytest.approx(2 * na * nb / (n * (n - 1)), rel=1e-15)
    combined = sum(weights[k] * rdf["partial"][k] for k in weights)
    assert np.max(np.abs(combined - rdf["g"])) < 1e-12
    # Against numpy over all pairs, from gsd.hoomd's reading of the same file.
    with gsd_hoomd.open(str(dense_binary / "run.gsd"), "rb") as trajectory:
        box = np.array(trajectory[0].configuration.box[:2], dtype=np.float64)
        types = np.array(trajectory[0].particles.typeid)
        frames = [np.array(f.particles.position[:, :2], dtype=np.float64) for f in trajectory]
    edges = np.arange(len(rdf["r"]) + 1) * rdf["bin_width"]
    g, partial, _ = direct_partials(frames, edges, box, types)
    # carom reads the single-precision positions; binning can differ only at a bin's edge.
    assert np.allclose(rdf["g"], g, atol=2e-2)
    for key in partial:
        assert np.allclose(rdf["partial"][key], partial[key], atol=5e-2), key
    # No pair closer than its contact distance (less the compression's round-off).
    lo = rdf["r"] + 0.5 * rdf["bin_width"]
    contact = {"A-A": 1.0, "A-B": 1.2, "B-B": 1.4}
    scale = 2 * carom.read(str(dense_binary / "dense.txt")).radii.min()
    for key, d in contact.items():
        assert np.all(rdf["partial"][key][lo < 0.99 * d * scale] == 0.0), key
    # The same through the command line's JSON.
    cli("analyze", dense_binary / "run.gsd", "-o", dense_binary / "analysis.json")
    out = json.loads((dense_binary / "analysis.json").read_text())
    assert out["rdf"]["g"] == rdf["g"].tolist()
    assert out["rdf"]["partial"]["A-B"] == rdf["partial"]["A-B"].tolist()
    # The mixture's relaxation too: F_s(k,t) at its main peak, from 1 at t = 0.
    fs = result["self_scattering"]
    assert fs is not None and fs["fs"][0] == pytest.approx(1.0, abs=1e-14)
    assert len(fs["fs"]) == len(result["msd"]["t"]) > 2


def test_one_type_files_have_no_types(cli, tmp_path):
    path = tmp_path / "one.txt"
    cli("init", "--n", 50, "--phi", 0.3, "-o", path)
    assert "types" not in path.read_text()
    sim = carom.read(path)
    assert sim.types == ["A"] and not sim.typeid.any()
    cli("run", path, 1, "--dump", tmp_path / "one.gsd", "--every", 0.5)
    result = carom.analyze(str(tmp_path / "one.gsd"))
    assert "partial" not in result["rdf"]


def test_sweep_plans_take_species(cli, tmp_path):
    plan = tmp_path / "plan.toml"
    plan.write_text('[start]\nn = 60\nboundary = "periodic"\nspecies = "A:0.5:1.0,B:0.5:1.4"\n'
                    '[run]\nend_time = 1\n[sweep]\nphi = [0.2, 0.3]\n')
    listing = cli("sweep", plan, "-o", tmp_path / "out", "--dry-run")
    assert listing.count("--species A:0.5:1.0,B:0.5:1.4") == 2
    cli("sweep", plan, "-o", tmp_path / "out", "-q")
    starts = sorted((tmp_path / "out").glob("*/start.txt"))
    assert len(starts) == 2
    for start in starts:
        names, types = types_of(start)
        assert names == ["A", "B"] and np.bincount(types).tolist() == [30, 30]
    plan.write_text(plan.read_text().replace('[run]', 'polydispersity = 0.1\n[run]'))
    message = cli.error("sweep", plan, "-o", tmp_path / "bad", "--dry-run")
    assert "species" in message and "polydispersity" in message


def test_final_states_and_checkpoints_keep_the_types(cli, tmp_path):
    start = tmp_path / "m.txt"
    cli("init", "--n", 60, "--phi", 0.3, "--species", BINARY, "--seed", 4, "-o", start)
    _, types = types_of(start)
    cli("run", start, 2, "--final", tmp_path / "end.gsd", "-o", "/dev/null", "-q")
    cli("run", tmp_path / "end.gsd", 1, "--final", tmp_path / "end.txt", "-o", "/dev/null", "-q")
    names, end_types = types_of(tmp_path / "end.txt")
    assert names == ["A", "B"] and np.array_equal(end_types, types)
    # A run resumed from its checkpoint ends as the whole run does, bit for bit, with the types.
    cli("run", start, 3, "--format", "csv", "-o", tmp_path / "whole.csv", "-q")
    cli("run", start, 1.5, "--checkpoint", tmp_path / "part.ckpt", "-o", "/dev/null", "-q")
    assert json.loads((tmp_path / "part.ckpt").read_text())["types"] == ["A", "B"]
    cli("run", "--resume", tmp_path / "part.ckpt", 3, "--format", "csv",
        "-o", tmp_path / "resumed.csv", "-q")
    assert (tmp_path / "whole.csv").read_bytes() == (tmp_path / "resumed.csv").read_bytes()
    sim = carom.resume(tmp_path / "part.ckpt")
    assert sim.types == ["A", "B"] and np.array_equal(sim.typeid, types)


def four_disks(**species):
    """Four disks of two sizes in a periodic box, built from arrays with `species`."""
    positions = np.array([[1.0, 1.0], [3.0, 1.0], [1.0, 3.0], [3.0, 3.0]])
    velocities = np.array([[1.0, 0.5], [-0.5, 1.0], [0.3, -1.0], [-1.0, -0.2]])
    return carom.Simulation(positions, velocities, [5.0, 5.0], radii=[0.4, 0.6, 0.4, 0.6],
                            boundary="periodic", **species)


def test_a_simulation_from_arrays_takes_types(tmp_path):
    gsd_hoomd = pytest.importorskip("gsd.hoomd")
    sim = four_disks(types=["small", "big"], typeid=np.array([0, 1, 0, 1]))
    assert sim.types == ["small", "big"]
    assert_bitwise_equal(sim.typeid, np.array([0, 1, 0, 1], dtype=np.uint32), "typeid")
    sim.run(2.0, dump=tmp_path / "m.gsd", every=1.0)
    assert sim.events > 0 and sim.types == ["small", "big"]
    with gsd_hoomd.open(str(tmp_path / "m.gsd"), "rb") as trajectory:
        assert len(trajectory) == 3
        for frame in trajectory:
            assert list(frame.particles.types) == ["small", "big"]
            assert frame.particles.typeid.tolist() == [0, 1, 0, 1]
    # Without them, one type "A"; one name alone needs no typeid.
    assert four_disks().types == ["A"] and four_disks().typeid.tolist() == [0] * 4
    assert four_disks(types=("B",)).types == ["B"]


@pytest.mark.parametrize("species, message", [
    ({"types": ["A", "B"], "typeid": [0, 1, 0]}, r"typeid must have shape \(4,\)"),
    ({"types": ["A", "B"], "typeid": [0, 1, 2, 1]}, r"type 2 of particle 2 .* 2 types \(0 to 1\)"),
    ({"types": ["A", "B"], "typeid": [0, -1, 0, 1]}, r"type -1 of particle 1"),
    ({"types": ["A", "B"], "typeid": [0.0, 1.0, 0.0, 1.0]}, r"typeid must be an array of integers"),
    ({"types": ["A", "B"]}, r"typeid= must say which"),
    ({"types": ["A", "A"], "typeid": [0, 1, 0, 1]}, r"type name A appears twice"),
    ({"types": ["A", ""], "typeid": [0, 1, 0, 1]}, r"type name \"\" must be letters"),
    ({"types": ["A", "B C"], "typeid": [0, 1, 0, 1]}, r"type name \"B C\" must be letters"),
    ({"types": [], "typeid": [0, 0, 0, 0]}, r"at least one type name"),
    ({"types": "AB", "typeid": [0, 1, 0, 1]}, r"types must be a list of names"),
], ids=["short", "beyond", "negative", "floats", "no-typeid", "twice", "empty", "space", "none",
        "str"])
def test_types_from_arrays_are_checked(species, message):
    with pytest.raises(ValueError, match=message):
        four_disks(**species)
