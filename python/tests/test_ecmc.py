"""Event-chain Monte Carlo (`--sampler ecmc`, sampler="ecmc") from every front end: the command
line, Python's read, init and Simulation, and sweeps give the same run; every output works; what
needs dynamics is refused by name. (The same files in pieces and from either front end:
test_run_parity.)"""

import json

import numpy as np
import pytest

import carom
from _support import assert_bitwise_equal


@pytest.fixture(params=[2, 3], ids=["disks", "spheres"])
def start(request, cli, tmp_path):
    """A periodic start file written by `carom init` at a packing where chains lift often."""
    dim = request.param
    path = tmp_path / "start.txt"
    n, phi = (300, 0.6) if dim == 2 else (256, 0.4)
    cli("init", "--dim", str(dim), "--n", str(n), "--phi", str(phi), "--seed", "4",
        "--boundary", "periodic", "-o", path)
    return path, dim


def test_the_summary_says_how_the_chains_ran(cli, tmp_path, start):
    """(The files of a run of chains in pieces and from either front end: test_run_parity.)"""
    start_file, dim = start
    path = tmp_path / "summary.json"
    cli("run", start_file, "6", "--equilibrate", "2", "--sampler", "ecmc", "--seed", "7", "-q",
        "--summary", path, "-o", tmp_path / "end.txt")
    summary = json.loads(path.read_text())
    assert summary["sampler"] == "ecmc" and summary["chain_seed"] == 7
    assert summary["lifts"] == summary["pair_collisions"] > 1000
    assert summary["temperature"] == 1.0
    # Z along each axis, and the pressure as beta P = Z N / V.
    assert len(summary["directional_compressibility_factor"]) == dim
    volume = float(np.prod(summary["box"]))
    assert summary["pressure"] == pytest.approx(
        summary["compressibility_factor"] * summary["n"] / volume, rel=1e-12)


def test_a_simulation_of_chains_says_so_as_its_summary_does(cli, tmp_path, start):
    """sim.sampler and sim.chain_length are the summary's; what only dynamics has (rule,
    restitution, tc, engine) is None, as the summary's null; repr speaks of chains and lifts."""
    start_file, _ = start
    path = tmp_path / "summary.json"
    sim = carom.read(start_file, sampler="ecmc", seed=7)
    sim.run(2, summary=path)
    summary = json.loads(path.read_text())
    assert (sim.sampler, sim.chain_length) == ("ecmc", summary["chain_length"])
    assert (sim.rule, sim.restitution, sim.tc, sim.engine) == (None, None, None, None)
    assert [summary[k] for k in ("rule", "restitution", "tc", "engine")] == [None] * 4
    assert f"{summary['lifts']} lifts" in repr(sim) and "event chains of" in repr(sim)
    dynamics = carom.read(start_file)
    assert (dynamics.sampler, dynamics.chain_length, dynamics.rule) == ("md", None, "elastic")


def test_the_pressure_tensor_and_errors_hold_for_chains_of_any_length(cli, tmp_path, start):
    """The tensor's diagonal is beta P along each axis, rho Z_k, however the chains' moves split
    among the axes (a chain longer than the run moves along x alone: nothing is known along y).
    An interval of the window that holds less than a turn of chains (one along every axis) is a
    piece of a chain, neither alike nor independent of the next: no error, no drift verdict.
    Regression: a chain as long as the run gave yy = 0 and xx twice beta P_x, and intervals
    inside one chain gave errors a tenth of the scatter between runs."""
    start_file, dim = start
    summaries = {}
    for length in ("100000", "0"):
        path = tmp_path / f"summary{length}.json"
        extra = ["--chain-length", length] if length != "0" else []
        cli("run", start_file, "4", "--sampler", "ecmc", "-q", "--summary", path,
            "-o", tmp_path / "end.txt", *extra)
        summaries[length] = json.loads(path.read_text())
    for summary in summaries.values():
        density = summary["n"] / float(np.prod(summary["box"]))
        z = summary["directional_compressibility_factor"]
        tensor = summary["pressure_tensor"]
        for axis, name in enumerate(("xx", "yy", "zz")[:dim]):
            if z[axis] is None:
                assert tensor[name] is None
            else:
                assert tensor[name] == pytest.approx(density * z[axis], rel=1e-12)
    one_chain = summaries["100000"]
    assert one_chain["directional_compressibility_factor"][1] is None
    assert one_chain["compressibility_factor_error"] is None
    assert one_chain["compressibility_factor_drift"] is None
    assert summaries["0"]["compressibility_factor_error"] > 0


def test_chains_round_a_ring_in_contact_stop_with_an_error_that_says_so(cli, tmp_path):
    """72 disks at 0.72 from carom init's lattice (seed 407): by t = 0.1217 the chains of seed 407
    have pushed each disk of a row up into contact with both of its neighbours in the row above
    (the lattice puts it exactly between them), which closes a ring of disks in contact all round
    the box along x. A chain along x then lifts round it for ever without moving: exactly, not by
    rounding (the clock creeps by an ulp now and then). The jam guard counts lifts that move the
    clock on by nothing a double resolves and stops the run, naming the ring and the way out.
    Regression: it counted lifts at one unchanged time only, and the run hung."""
    start = tmp_path / "start.txt"
    cli("init", "--n", "72", "--phi", "0.72", "--boundary", "periodic", "--seed", "407",
        "-o", start)
    message = cli.error("run", start, "1", "--sampler", "ecmc", "--seed", "407", "-q",
                        "-o", tmp_path / "end.txt", expect=1)
    assert "jammed" in message and "without time advancing" in message
    assert "ring of disks in contact across the box along x" in message
    # The way out it names works: one unit of dynamics, then the same chains.
    melted = tmp_path / "melted.txt"
    cli("run", start, "1", "-q", "--final", melted, "-o", tmp_path / "table.txt")
    cli("run", melted, "1", "--sampler", "ecmc", "--seed", "407", "-q", "-o", tmp_path / "end.txt")


def test_other_seeds_give_other_chains_and_the_same_seed_the_same(cli, tmp_path, start):
    start_file, dim = start
    ends = {}
    for seed in (1, 1, 2):
        out = tmp_path / f"end{len(ends)}.txt"
        cli("run", start_file, "2", "--sampler", "ecmc", "--seed", str(seed), "-q", "-o", out)
        ends[len(ends)] = out.read_bytes()
    assert ends[0] == ends[1]
    assert ends[0] != ends[2]


def test_init_and_arrays_give_the_command_lines_run(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "200", "--phi", "0.55", "--seed", "3", "--boundary", "periodic", "-o", start)
    summary = tmp_path / "cli.json"
    cli("run", start, "3", "--sampler", "ecmc", "--seed", "3", "--chain-length", "4", "-q",
        "--summary", summary, "-o", tmp_path / "end.txt")
    expected = json.loads(summary.read_text())

    by_init = carom.init(200, 0.55, seed=3, boundary="periodic", sampler="ecmc", chain_length=4)
    read = carom.read(start, sampler="ecmc", seed=3, chain_length=4)
    arrays = carom.Simulation(read.positions, read.velocities, read.box, radii=read.radii,
                              boundary="periodic", sampler="ecmc", chain_length=4, seed=3)
    for name, sim in [("init", by_init), ("read", read), ("arrays", arrays)]:
        sim.run(3)
        got = sim.observables()
        for key in ("lifts", "compressibility_factor", "directional_compressibility_factor",
                    "pressure_tensor", "chain_length", "chain_seed", "sampler"):
            assert got[key] == expected[key], f"{name}: {key}"
        # What only dynamics has is null: the one moving particle's speed is a unit of the
        # sampler's clock, not a temperature (its kinetic energy is (N d)^2 / 2).
        for key in ("rule", "restitution", "tc", "engine", "kinetic_energy_initial",
                    "kinetic_energy_final", "momentum_final", "degrees_of_freedom"):
            assert got[key] is None and expected[key] is None, f"{name}: {key}"
        assert got["temperature"] == 1.0
    assert_bitwise_equal(by_init.positions, read.positions, "positions")


@pytest.mark.parametrize("options, words", [
    (["--shear", "0.1"], "--shear needs dynamics (--sampler md)"),
    (["--thermostat", "rescale", "--kT", "1", "--thermostat-every", "1"],
     "--thermostat needs dynamics (--sampler md)"),
    # Refused for what it is, not for the --kT it lacks (which would not make it work).
    (["--thermostat", "andersen", "--thermostat-rate", "1"],
     "--thermostat needs dynamics (--sampler md)"),
    (["--kT", "1"], "--kT needs dynamics (--sampler md)"),
    (["--rule", "elastic"], "--rule needs dynamics (--sampler md)"),
    (["--restitution", "0.9", "--rule", "elastic"], "--restitution needs dynamics"),
    (["--engine", "reference"], "--engine reference needs dynamics"),
    (["--transport"], "--transport needs dynamics (--sampler md)"),
    (["--chain-length", "-1"], "--chain-length must be a number above 0"),
    (["--tc", "0.1"], "--tc needs dynamics (--sampler md)"),
])
def test_what_needs_dynamics_is_refused_by_name(cli, tmp_path, options, words):
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    message = cli.error("run", start, "1", "--sampler", "ecmc", *options)
    assert words in message


def test_walls_are_refused(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "walls", "-o", start)
    message = cli.error("run", start, "1", "--sampler", "ecmc")
    assert "--sampler ecmc needs a periodic box (--boundary periodic)" in message


def test_python_words_the_refusals_its_own_way(tmp_path):
    with pytest.raises(ValueError, match='sampler="ecmc" needs a periodic box'):
        carom.init(50, 0.3, boundary="walls", sampler="ecmc")
    with pytest.raises(ValueError, match='shear= needs dynamics'):
        carom.init(50, 0.3, boundary="periodic", sampler="ecmc", shear=0.1)
    masses = carom.init(50, 0.3, boundary="periodic")
    with pytest.raises(ValueError, match="every mass must be 1"):
        carom.Simulation(masses.positions, masses.velocities, masses.box, masses=2.0,
                         boundary="periodic", sampler="ecmc")


def test_what_chains_would_ignore_is_refused_from_python_too(cli, tmp_path):
    """kT and rule have defaults in Python (1, elastic): other values were asked for, and chains
    would ignore them. A chain length without chains is refused by every front end."""
    with pytest.raises(ValueError, match='kT= needs dynamics'):
        carom.init(50, 0.3, boundary="periodic", sampler="ecmc", kT=2.0)
    with pytest.raises(ValueError, match='rule= needs dynamics'):
        carom.init(50, 0.3, boundary="periodic", sampler="ecmc", rule="swap")
    gas = carom.init(50, 0.3, boundary="periodic")
    with pytest.raises(ValueError, match='rule= needs dynamics'):
        carom.Simulation(gas.positions, gas.velocities, gas.box, boundary="periodic",
                         sampler="ecmc", rule="swap")
    with pytest.raises(ValueError, match='chain_length= needs sampler="ecmc"'):
        carom.init(50, 0.3, boundary="periodic", chain_length=3.0)
    with pytest.raises(ValueError, match='tc= needs dynamics'):
        carom.init(50, 0.3, boundary="periodic", sampler="ecmc", tc=0.1)
    with pytest.raises(ValueError, match='thermostat= needs dynamics'):
        carom.init(50, 0.3, boundary="periodic", sampler="ecmc", thermostat="rescale")
    # The magnitudes carom's command line takes, in every front end.
    for length in (1e300, 1e-300):
        with pytest.raises(ValueError, match="chain_length= is out of range"):
            carom.init(50, 0.3, boundary="periodic", sampler="ecmc", chain_length=length)
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    assert "--chain-length needs --sampler ecmc" in cli.error("run", start, "1", "--chain-length", "3")
    plan = tmp_path / "plan.toml"
    plan.write_text('[start]\nn = 50\nphi = 0.3\nboundary = "periodic"\n'
                    '[run]\nend_time = 1\nchain_length = 3\n[sweep]\nseed = [1, 2]\n')
    assert "needs" in cli.error("sweep", plan, "-o", tmp_path / "out")
    # Chains that a task's run would refuse are refused with the plan, before anything runs.
    for setting, words in (("chain_length = 1e300", "--chain-length is out of range"),
                           ("chain_length = 1e-7",
                            "chain_length = 1e-07: 10 is too late for event chains"),
                           ("tc = 0.1", "--tc needs dynamics"),
                           ('thermostat = "rescale"', "--thermostat needs dynamics")):
        plan.write_text('[start]\nn = 64\nphi = 0.3\nboundary = "periodic"\n[run]\n'
                        f'sampler = "ecmc"\nend_time = 10\n{setting}\n[sweep]\nseed = [1, 2]\n')
        message = cli.error("sweep", plan, "-o", tmp_path / "out", "--dry-run")
        assert "plan.toml:" in message and words in message, message


def test_a_seed_alone_still_needs_something_to_seed(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    assert "--seed needs --kT T" in cli.error("run", start, "1", "--seed", "3")
    cli("run", start, "1", "--seed", "3", "--sampler", "ecmc", "-q", "-o", tmp_path / "end.txt")


def test_every_output_shows_the_particles_at_rest(cli, tmp_path, start):
    """Chains sample positions: the table, json, frames (.xyz, .lammpstrj, .gsd), the end state
    and Python's velocities give every particle velocity 0, as the summary's kinetic energy
    does (the one moving particle's speed is the sampler's clock); dynamics' are the velocities."""
    import gsd.hoomd
    start_file, dim = start
    run = ("run", start_file, "3", "--sampler", "ecmc")
    table = cli(*run, "-q").splitlines()[1:]
    assert all(line.split(") (")[1].startswith(", ".join(["0.000000"] * dim)) for line in table)
    particles = json.loads(cli(*run, "--format", "json", "-q"))["particles"]
    assert all(p[v] == 0.0 for p in particles for v in ("vx", "vy", "vz")[:dim])
    for name in ("f.xyz", "f.lammpstrj"):
        cli(*run, "--dump", tmp_path / name, "--every", "1", "-q", "-o", tmp_path / "end.txt")
    xyz = [line.split() for line in (tmp_path / "f.xyz").read_text().splitlines()]
    assert all(row[4:7] == ["0", "0", "0"] for row in xyz
               if len(row) > 10 and not row[0].startswith("Lattice="))
    lammps = (tmp_path / "f.lammpstrj").read_text().split("ITEM: ATOMS ")[1:]
    columns = lammps[0].splitlines()[0].split()
    at = [columns.index(c) for c in ("vx", "vy", "vz")[:dim]]
    rows = [row.split() for frame in lammps for row in frame.splitlines()[1:]]
    atoms = [row for row in rows if len(row) == len(columns)]
    assert len(atoms) == 4 * len(particles)
    assert all(float(row[k]) == 0.0 for row in atoms for k in at)
    cli(*run, "--dump", tmp_path / "f.gsd", "--every", "1", "-q", "-o", tmp_path / "end.txt")
    assert all(not np.any(f.particles.velocity) for f in gsd.hoomd.open(tmp_path / "f.gsd"))
    sim = carom.read(start_file, sampler="ecmc")
    sim.run(3)
    assert not np.any(sim.velocities)
    dynamics = carom.read(start_file)
    dynamics.run(1)
    assert np.any(dynamics.velocities)


def test_every_output_reads_back(cli, tmp_path):
    start = tmp_path / "start.txt"
    cli("init", "--n", "400", "--phi", "0.65", "--seed", "2", "--boundary", "periodic", "-o", start)
    frames, log = tmp_path / "frames.gsd", tmp_path / "log.csv"
    cli("run", start, "20", "--sampler", "ecmc", "--check", "--dump", frames, "--every", "2",
        "--log", log, "--log-every", "2", "-q", "-o", tmp_path / "end.txt")
    report = json.loads(cli("analyze", frames, "-o", "-"))
    assert report["frames"]["count"] == 11
    # Chains move the centre of mass along +x and +y (10 diameters in all over 20 units), which
    # the MSD holds unless it is taken from the centre of mass (--com, com=True); either front end
    # gives the same analysis.
    assert report["msd"]["centre_of_mass_shift"] == pytest.approx(20 / np.sqrt(2), rel=0.01)
    assert not report["msd"]["from_centre_of_mass"]
    assert any("the centre of mass moved by" in w for w in report["warnings"])
    relative = json.loads(cli("analyze", frames, "--com", "-o", "-"))
    assert relative["msd"]["from_centre_of_mass"]
    assert not any("the centre of mass moved by" in w for w in relative["warnings"])
    assert relative["msd"]["msd"][-1] < report["msd"]["msd"][-1] / 2
    assert relative["self_scattering"]["fs"] != report["self_scattering"]["fs"]
    from_python = carom.analyze(frames, com=True)
    assert_bitwise_equal(from_python["msd"]["msd"], np.array(relative["msd"]["msd"]), "MSD")
    assert_bitwise_equal(from_python["self_scattering"]["fs"],
                         np.array(relative["self_scattering"]["fs"]), "F_s")
    rows = log.read_text().splitlines()
    header = rows[0].split(",")
    last = dict(zip(header, rows[-1].split(",")))
    assert float(last["temperature"]) == 1.0
    # The pressure tensor in beta P, as the pressure: its trace over D is about the pressure.
    trace = (float(last["pxx"]) + float(last["pyy"])) / 2
    assert trace == pytest.approx(float(last["pressure"]), rel=0.05)


def test_a_log_it_cannot_continue_is_refused_and_kept(cli, tmp_path):
    """An event-chain log of carom before 1.9 (dynamics' Gxx, ... columns, where chains now keep
    Kxx, ... and Wxx, ...) cannot be continued: a resumed run refuses it (exit 2) rather than
    starting it again and losing its rows."""
    start, log, checkpoint = tmp_path / "start.txt", tmp_path / "log.csv", tmp_path / "run.ckpt"
    cli("init", "--n", "64", "--phi", "0.3", "--boundary", "periodic", "-o", start)
    cli("run", start, "2", "--sampler", "ecmc", "--log", log, "--log-every", "0.5",
        "--checkpoint", checkpoint, "-q", "-o", tmp_path / "end.txt")
    header, *rows = log.read_text().splitlines()
    assert header.endswith(",pxx,pyy,pxy,Kxx,Kyy,Wxx,Wyy,Wxy")
    old = header.replace(",Kxx,Kyy,Wxx,Wyy,Wxy", ",Gxx,Gyy,Gxy")
    log.write_text("\n".join([old] + [",".join(row.split(",")[:-2]) for row in rows]) + "\n")
    before = log.read_bytes()
    message = cli.error("run", "--resume", checkpoint, "4", "--log", log, "--log-every", "0.5",
                        "-q", "-o", tmp_path / "end.txt")
    assert "cannot continue" in message and "event-chain log of carom before 1.9" in message
    assert log.read_bytes() == before
