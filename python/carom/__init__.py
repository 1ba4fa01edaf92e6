"""carom: event-driven molecular dynamics of hard disks and hard spheres.

The engine of the ``carom`` command line, driven from Python with numpy arrays. A run gives the
command line's results bit for bit::

    import carom

    sim = carom.read("examples/normal.txt")                 # a classic file, disks or spheres
    sim.run(20.0)
    print(sim.positions)                                   # (N, 2) float64, at sim.time

    sim = carom.init(n=4096, phi=0.5, seed=1, boundary="periodic", rule="elastic")
    sim.run(50.0)
    sim.reset_measurement()                                # equilibrated: measure from now
    sim.run(150.0, dump="movie.xyz", every=1.0)
    print(sim.observables()["compressibility_factor"])
    sim.save("run.ckpt")                                   # `carom run --resume run.ckpt` reads it

    dense, summary = carom.compress(sim, phi=0.7)          # `carom compress`: growing disks
    result = carom.analyze("movie.xyz", equilibrate=50)    # `carom analyze`: g(r), MSD, psi6
    table = carom.sweep("eos.toml", "eos")                 # `carom sweep`, its tasks on Dask

Use Debian's interpreter, ``/usr/bin/python3``, which has numpy and which the module is built for.
Bad arguments raise ``ValueError`` with the command line's messages; a broken file raises
``carom.InputError`` (a ``ValueError``) naming the file and line; a run that cannot go on (jammed
particles) raises ``carom.JamError`` (a ``RuntimeError``). Ctrl-C during ``run`` raises
``KeyboardInterrupt`` within a fraction of a second and leaves the simulation whole: it can be
saved or run on.
"""

import csv as _csv
import json as _json
import math as _math
import numbers as _numbers
import os as _os
import uuid as _uuid

import numpy as _np

from . import _carom
from ._carom import InputError, JamError

__version__ = _carom.__version__
# Every default a signature below shows is the library's, read from it here.
_D = _carom.defaults
__all__ = ["Simulation", "read", "init", "resume", "compress", "analyze", "sweep", "InputError",
           "JamError", "__version__"]

def _float_array(name, value, shape=None):
    """value as a C-contiguous float64 array of `shape` (None: any; an entry None: any length),
    or ValueError."""
    if isinstance(value, _np.ndarray) and value.dtype != _np.float64:
        raise ValueError(f"{name} must be a float64 array, got dtype {value.dtype}")
    try:
        array = _np.ascontiguousarray(value, dtype=_np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be an array of numbers: {error}") from None
    if shape is None:
        return array
    if array.ndim != len(shape) or any(s is not None and s != a for s, a in zip(shape, array.shape)):
        wanted = ", ".join("N" if s is None else str(s) for s in shape)
        wanted = f"({wanted},)" if len(shape) == 1 else f"({wanted})"
        raise ValueError(f"{name} must have shape {wanted}, got {array.shape}")
    return array


def _per_particle(name, value, n, default):
    """A number or an (N,) array as an (N,) float64 array."""
    if value is None:
        value = default
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number or an array of {n} numbers, got {value!r}")
    if isinstance(value, _numbers.Real):
        return _np.full(n, float(value))
    return _float_array(name, value, (n,))


def _number(name, value):
    """A finite float, as the command line reads numbers."""
    if isinstance(value, bool) or not isinstance(value, _numbers.Real):
        raise ValueError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not _math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value}")
    return value


def _whole(name, value, least=0, most=2**63 - 1):
    if isinstance(value, bool) or not isinstance(value, _numbers.Integral):
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    if value < least:
        raise ValueError(f"{name} must be at least {least}, got {value}")
    if value > most:
        raise ValueError(f"{name} must be at most {most}, got {value}")
    return int(value)


def _choice(name, value, names):
    if not isinstance(value, str) or value not in names:
        raise ValueError(f"{name} must be one of {', '.join(names)}, got {value!r}")
    return value


def _flag(name, value):
    if not isinstance(value, (bool, _np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def _path(value):
    """A file name (str, bytes or os.PathLike) as the bytes that name the file; None as b"" (no
    file). Bytes, not str: a name that is not UTF-8 (os.fsdecode's surrogate escapes) reaches the
    library as the file's own name."""
    if value is None:
        return b""
    return _os.fsencode(value if isinstance(value, (str, bytes, _os.PathLike)) else str(value))


def _output(name, path, every_name, every):
    """A streamed output and its cadence, both or neither: (_path(path) or b"", every or 0.0)."""
    if path is None:
        if every is not None:
            raise ValueError(f"{every_name} needs {name}: the file to write to")
        return b"", 0.0
    if every is None:
        raise ValueError(f"{name} needs {every_name}: the time between "
                         f"{'frames' if name == 'dump' else 'rows'}")
    return _path(path), _number(every_name, every)


_RULES = ("swap", "elastic")
_BOUNDARIES = ("walls", "periodic")
_ENGINES = ("fast", "reference")


class Simulation:
    """A run of hard disks (dim 2) or spheres (dim 3): its state, its engine and its measurement.

    positions, velocities: (N, D) float64 arrays at t = 0 (D = 2 or 3); box: the D sides (the box
    is [0, Lx] x [0, Ly] [x [0, Lz]]); radii, masses: a number or an (N,) array. boundary:
    "walls" (hard walls on every face) or "periodic". rule: "elastic" (momentum exchanged along
    the line of centres, with masses: real hard particles) or "swap" (the classic assignment's:
    touching particles exchange whole velocities); restitution < 1 makes elastic collisions inelastic, and a particle that
    collided less than `tc` ago collides elastically (the TC model against inelastic collapse).
    engine: "fast" (O(1) per event) or "reference" (the classic assignment's O(N^2) algorithm, for checking).

    The start is checked as `carom run` checks a file: finite numbers, positive radii and
    masses, particles inside the box, clear of the walls and of each other (touching is fine);
    anything else is a ValueError saying what and which particle.

    carom.read, carom.init and carom.resume make Simulations from a file, from `carom init`'s
    options, and from a checkpoint.
    """

    def __init__(self, positions, velocities, box, radii=_D["radius"], masses=_D["mass"],
                 boundary=_D["boundary"], rule=_D["rule"], restitution=_D["restitution"],
                 tc=_D["tc"], engine=_D["engine"]):
        positions = _float_array("positions", positions)
        if positions.ndim != 2 or positions.shape[1] not in (2, 3) or positions.shape[0] < 1:
            raise ValueError(f"positions must have shape (N, 2) or (N, 3) with N >= 1, "
                             f"got {positions.shape}")
        n, d = positions.shape
        velocities = _float_array("velocities", velocities, (n, d))
        box = _float_array("box", box, (d,))
        radii = _per_particle("radii", radii, n, _D["radius"])
        masses = _per_particle("masses", masses, n, _D["mass"])
        self._running = False
        self._core = _carom.Simulation.from_arrays(
            positions, velocities, box, radii, masses, _choice("boundary", boundary, _BOUNDARIES),
            _choice("rule", rule, _RULES), _number("restitution", restitution), _number("tc", tc),
            _choice("engine", engine, _ENGINES))

    @classmethod
    def _wrap(cls, core):
        simulation = cls.__new__(cls)
        simulation._running = False
        simulation._core = core
        return simulation

    @property
    def _idle(self):
        """The engine, when no run is under way (in another thread, with the GIL released)."""
        if self._running:
            raise RuntimeError("this simulation is running (in another thread): wait for run()")
        return self._core

    def run(self, t, dump=None, every=None, log=None, log_every=None, events=None,
            checkpoint=None, checkpoint_every=None, summary=None, check=False, check_every=None,
            equilibrate=None, transport=False, collisions=False):
        """Runs to time t (absolute: not before sim.time) and returns the collision log if asked.

        Every event up to t is processed in time order; any sequence of runs ends exactly as one
        run to the last time would. The GIL is released while the engine works. The options are
        `carom run`'s, with the same meaning and the same files, byte for byte:

        dump, every: a trajectory written as the run goes, a frame every `every` time units (at
        multiples of `every`, so frames stay evenly spaced: a new dump's first frame is at
        sim.time when that is a multiple, else at the next one): ".xyz" (extended XYZ, for ASE
        and OVITO), ".lammpstrj" or ".gsd".
        log, log_every: the time series (csv; `carom run --log`). events: every collision (csv).
        checkpoint: saved at the end, on Ctrl-C, and every checkpoint_every (a number of events,
        or seconds as "600s"). summary: the json of observables() written at the end.
        check: verify as the run goes that event times never decrease and, every check_every
        events, that nothing overlaps. equilibrate: open the measurement window at that time.
        transport: measure the self-diffusion coefficient, shear viscosity and thermal
        conductivity over the measurement window (a periodic box; observables()["transport"]).
        A file named again by the next run with the same cadence goes on; a Simulation from
        carom.resume continues its files as `carom run --resume` does (cut at its time, then
        appended to); otherwise a file begins anew.
        collisions: when True, returns a numpy structured array of this run's collisions with
        fields time (float64), i and j (int64; j < 0 is a wall label, -1 left, -2 right, -3
        bottom, -4 top, -5 back, -6 front), as `carom run --events` logs them.
        """
        t = _number("t", t)
        dump, every = _output("dump", dump, "every", every)
        log, log_every = _output("log", log, "log_every", log_every)
        if checkpoint_every is not None:
            if checkpoint is None:
                raise ValueError("checkpoint_every needs checkpoint: the file to save to")
            if isinstance(checkpoint_every, str):
                checkpoint_every = checkpoint_every.strip()
            else:
                checkpoint_every = str(_whole("checkpoint_every", checkpoint_every, 1))
        if check_every is not None and not check:
            raise ValueError("check_every needs check=True")
        check_every = 0 if check_every is None else _whole("check_every", check_every, 1)
        core = self._idle
        self._running = True
        try:
            core.run(t, dump, every, log, log_every, _path(events), _path(checkpoint),
                     checkpoint_every, _path(summary), _flag("check", check), check_every,
                     None if equilibrate is None else _number("equilibrate", equilibrate),
                     _flag("transport", transport), _flag("collisions", collisions))
        finally:
            self._running = False
        return core.collisions() if collisions else None

    def advance(self, dt, **options):
        """Runs for dt more time units (HOOMD's sim.run(steps) habit): sim.run(sim.time + dt, ...).
        The end time is the double sim.time + dt, so many small advances can land a hair off
        round times; run(t) names a time exactly. The options are run()'s."""
        dt = _number("dt", dt)
        if not dt >= 0.0:
            raise ValueError(f"dt must be >= 0, got {dt}")
        return self.run(self.time + dt, **options)

    def collisions(self):
        """The collisions logged and not yet returned (after a KeyboardInterrupt, say)."""
        return self._idle.collisions()

    @property
    def time(self):
        """The time the run has reached."""
        return self._idle.time

    @property
    def events(self):
        """Collisions processed since the run began (across checkpoints)."""
        return self._idle.events

    @property
    def n(self):
        """The number of particles."""
        return self._idle.n

    @property
    def dim(self):
        """2 for disks, 3 for spheres."""
        return self._idle.dim

    @property
    def box(self):
        """The box's sides, a (D,) float64 array."""
        return self._idle.box

    @property
    def boundary(self):
        """"walls" (hard walls on every face) or "periodic" (minimum image, no walls)."""
        return self._idle.boundary

    @property
    def rule(self):
        """"elastic" (momentum exchanged along the line of centres, with masses) or "swap" (the
        classic assignment's: whole velocities exchanged)."""
        return self._idle.rule

    @property
    def restitution(self):
        """The coefficient of normal restitution: 1 elastic, below 1 inelastic (granular)."""
        return self._idle.restitution

    @property
    def tc(self):
        """The TC model's time: a particle that collided less than tc ago collides elastically
        (against inelastic collapse; no effect at restitution 1)."""
        return self._idle.tc

    @property
    def engine(self):
        """"fast" (neighbour lists or cells and an event calendar) or "reference" (every pair
        checked after every event: O(N^2), for checking); both give the same events, bit for
        bit."""
        return self._idle.engine

    @property
    def positions(self):
        """Every particle's centre at sim.time, wrapped into a periodic box: (N, D) float64 (a copy)."""
        return self._idle.positions

    @property
    def images(self):
        """Every particle's image flags at sim.time: (N, D) int32, the box sides it has crossed
        (HOOMD's and LAMMPS' convention; zero with walls). In a sheared box the image one box up
        lies at (sim.shear_shift, Ly), as in HOOMD's tilted box of tilt xy = shear_shift / Ly."""
        return self._idle.images

    @property
    def shear_shift(self):
        """In a sheared box (shear=), the x shift of the images one box up at sim.time, within
        half a side of 0; 0.0 otherwise."""
        return self._idle.shear_shift

    @property
    def unwrapped_positions(self):
        """positions + images * box (plus images_y * shear_shift along x in a sheared box): where
        each particle would be had the box not wrapped it, (N, D) float64 (for displacements and
        the mean squared displacement)."""
        core = self._idle
        unwrapped = core.positions + core.images * _np.asarray(core.box)
        unwrapped[:, 0] += core.images[:, 1] * core.shear_shift
        return unwrapped

    @property
    def velocities(self):
        """Every particle's velocity at sim.time: (N, D) float64 (a copy)."""
        return self._idle.velocities

    @property
    def radii(self):
        """Each particle's radius: (N,) float64 (a copy)."""
        return self._idle.radii

    @property
    def masses(self):
        """Each particle's mass: (N,) float64 (a copy)."""
        return self._idle.masses

    @property
    def wall_collisions(self):
        """Each particle's wall collisions so far: (N,) uint64."""
        return self._idle.wall_collisions

    @property
    def pair_collisions(self):
        """Each particle's collisions with other particles so far: (N,) uint64."""
        return self._idle.pair_collisions

    def observables(self):
        """The json summary of `carom run --summary` as a dict: the same keys and values.

        Pressure (collision virial), Z = PV/NkT, kT (over D(N - 1) degrees of freedom in a
        periodic box), wall pressure, collision rate and mean free time, measured over the
        window opened by reset_measurement or measure_from (from t = 0 by default).
        """
        return _json.loads(self._idle.json(False))

    def reset_measurement(self):
        """Opens the measurement window now: counts from zero, the kinetic energy now."""
        self._idle.reset_measurement()

    def measure_from(self, t):
        """Opens the measurement window at time t (as `carom run --equilibrate t`)."""
        self._idle.measure_from(_number("measure_from", t))

    def format(self, kind="table"):
        """The command line's output at sim.time: "table", "csv" or "json" (with particles)."""
        return self._idle.text(_choice("format", kind, ("table", "csv", "json")))

    def save(self, path):
        """Writes a checkpoint (atomically) that carom.resume and `carom run --resume` continue."""
        self._idle.save(_path(path))

    def __repr__(self):
        kind = "disks" if self.dim == 2 else "spheres"
        return (f"<carom.Simulation: {self.n} {kind}, t = {self.time}, {self.events} events, "
                f"{self.boundary}, {self.rule}>")


def read(path, rule=None, boundary=None, restitution=_D["restitution"], tc=_D["tc"],
         engine=_D["engine"], kT=None, seed=_D["seed"], thermostat="none", thermostat_every=None,
         thermostat_rate=None, shear=None, velocity_profile=False):
    """A Simulation from a classic input file (two box sides: disks; three: spheres), or from a
    frame of a GSD file: "movie.gsd" (the last frame) or "movie.gsd:K" (periodic, as HOOMD's).

    The options are `carom run`'s. rule and boundary left None take what the file records
    (carom init and carom compress write `# carom: boundary=... rule=...`; a GSD frame is
    elastic in its own box); a plain classic file gets walls and the classic assignment's swap
    rule, or elastic with boundary="periodic" or restitution < 1. sim.rule and sim.boundary say
    which. kT: new Maxwell-Boltzmann velocities at that temperature, reproducible from seed, as
    `carom run --kT T --seed S` (for a start without velocities, or to rethermalise one).
    thermostat: "rescale" or "andersen" holds the run at kT every thermostat_every (Andersen's
    with thermostat_rate resets per particle per unit time), as `carom run --thermostat`.
    shear: a Lees-Edwards shear rate for a periodic box, with velocity_profile=True adding its
    streaming profile to the velocities, as `carom run --shear RATE --velocity-profile`. A
    broken file raises carom.InputError naming the file and line.
    """
    return Simulation._wrap(_carom.Simulation.read(
        _path(path), None if boundary is None else _choice("boundary", boundary, _BOUNDARIES),
        None if rule is None else _choice("rule", rule, _RULES),
        _number("restitution", restitution), _number("tc", tc),
        _choice("engine", engine, _ENGINES), None if kT is None else _number("kT", kT),
        _whole("seed", seed, 0, 2**64 - 1), *_thermostat(thermostat, thermostat_every,
                                                         thermostat_rate),
        *_shear(shear, velocity_profile)))


def init(n, phi, seed=_D["seed"], dim=_D["dim"], boundary=_D["boundary"], rule=_D["rule"],
         box=None, aspect=_D["aspect"], radius=None, polydispersity=_D["polydispersity"],
         kT=_D["kT"], placement=_D["placement"], restitution=_D["restitution"], tc=_D["tc"],
         engine=_D["engine"], thermostat="none", thermostat_every=None, thermostat_rate=None,
         shear=None, velocity_profile=False):
    """A Simulation of `carom init`'s start: the same particles, bit for bit.

    n particles at packing fraction phi with Maxwell-Boltzmann velocities at kT (zero momentum,
    exact temperature), reproducible from seed. dim 2: disks (random placement up to phi = 0.4,
    a triangular lattice above, up to 0.9069); dim 3: spheres (random up to 0.25, FCC above, up
    to 0.7405 for n = 4 k^3 in a periodic cube). box: the sides (the radius follows); else a
    square or cube (aspect = Lx / Ly) of spheres of `radius` (default 0.5). placement: "auto",
    "random" or "lattice". The run's options (rule, restitution, tc, engine, thermostat,
    thermostat_every, thermostat_rate holding the run at kT, and shear, velocity_profile) are
    `carom run`'s.
    """
    box = [] if box is None else [float(side) for side in _float_array("box", box, (None,))]
    return Simulation._wrap(_carom.Simulation.init(
        _whole("dim", dim, 2, 3), _whole("n", n, 1), _number("phi", phi), box,
        _number("aspect", aspect), None if radius is None else _number("radius", radius),
        _number("polydispersity", polydispersity), _number("kT", kT),
        _whole("seed", seed, 0, 2**64 - 1), _choice("boundary", boundary, _BOUNDARIES),
        _choice("placement", placement, ("auto", "random", "lattice")), _choice("rule", rule, _RULES),
        _number("restitution", restitution), _number("tc", tc),
        _choice("engine", engine, _ENGINES),
        *_thermostat(thermostat, thermostat_every, thermostat_rate),
        *_shear(shear, velocity_profile)))


def _shear(rate, profile):
    """The shear's arguments, checked as the other options are."""
    return (None if rate is None else _number("shear", rate),
            _flag("velocity_profile", profile))


def _thermostat(kind, every, rate):
    """The thermostat's arguments, checked as the other options are."""
    return (_choice("thermostat", kind, ("none", "rescale", "andersen")),
            None if every is None else _number("thermostat_every", every),
            None if rate is None else _number("thermostat_rate", rate))


def compress(sim, phi=None, jam=False, rate=_D["rate"], kT=_D["compress_kT"],
             jam_pressure=_D["jam_pressure"], unit_diameter=False):
    """`carom compress` of sim's particles at sim.time: a new Simulation (sim's rule, restitution,
    tc and engine; time 0) and the summary `carom compress --summary` writes, as a dict (status,
    packing_fraction, compressibility_factor, rate, kT, jam_pressure, time, events,
    mean_diameter, unit_diameter, box, ...). sim is left as it was.

    The diameters grow, so the packing's unit of length is the start's and its mean diameter is
    larger than the start's; unit_diameter=True rescales it (box, positions, radii) to a mean
    diameter of 1, as `carom compress --unit-diameter`.

    Every radius grows as r(t) = r(0) (1 + rate t), size ratios kept, while the particles move and
    collide (Lubachevsky-Stillinger); the velocities are rescaled to kT every N collisions. Give
    phi (stop exactly at that packing fraction) or jam=True (grow until the compressibility factor
    passes jam_pressure). Impossible requests (phi beyond close packing, overlapping particles)
    raise ValueError; Ctrl-C raises KeyboardInterrupt.
    """
    if (phi is None) == (not _flag("jam", jam)):
        raise ValueError("give phi (a packing fraction to stop at) or jam=True, not both")
    core, summary = sim._idle.compress(
        None if phi is None else _number("phi", phi), _number("rate", rate), _number("kT", kT),
        _number("jam_pressure", jam_pressure), _flag("unit_diameter", unit_diameter))
    return Simulation._wrap(core), _json.loads(summary)


def resume(path):
    """The Simulation a checkpoint holds (sim.save or `carom run --checkpoint`), to run on exactly."""
    return Simulation._wrap(_carom.Simulation.resume(_path(path)))


def _positive(name, value):
    """None (the default) as 0, else a number greater than 0."""
    if value is None:
        return 0.0
    value = _number(name, value)
    if not value > 0:
        raise ValueError(f"{name} must be greater than 0, not {value}")
    return value


def analyze(trajectory, equilibrate=None, bin=None, r_max=None, contact_width=None, log=None,
            html=None):
    """`carom analyze` on a .gsd or .xyz trajectory: a dict of its JSON, arrays as numpy arrays.

    Keys: "rdf" (r, g, bin_width, r_max, contact: {r, g, Z} or None), "msd" (t, msd) or None,
    "psi6" (t, global, local_mean) or None, "snapshot" (the last frame's positions, an (N, D)
    array, radii, and local psi6 as psi6_modulus and psi6_phase), "time", "packing_fraction",
    "warnings" (why an analysis is absent), ... Frames before `equilibrate` are left out; bin
    (default d / 50), r_max (5 d) and contact_width (d / 10) are the command's --bin, --r-max and
    --contact-width. `log` adds a `carom run --log` table to the result and the page; `html`
    writes the report page there. A broken file raises carom.InputError, bad options ValueError.
    """
    result = _json.loads(_carom.analyze(
        _path(trajectory), -1e300 if equilibrate is None else _number("equilibrate", equilibrate),
        _positive("bin", bin), _positive("r_max", r_max),
        _positive("contact_width", contact_width), None if log is None else _path(log),
        None if html is None else _path(html)))
    arrays = {"rdf": ("r", "g"), "msd": ("t", "msd"), "psi6": ("t", "global", "local_mean"),
              "snapshot": ("radius", "psi6_modulus", "psi6_phase")}
    for section, keys in arrays.items():
        for key in keys:
            if result[section] is not None and result[section][key] is not None:
                result[section][key] = _np.array(result[section][key], dtype=_np.float64)
    snapshot = result["snapshot"]
    snapshot["position"] = _np.array(snapshot["position"], dtype=_np.float64).reshape(
        -1, result["dimension"])
    result["time"] = _np.array(result["time"], dtype=_np.float64)
    return result


def _file_name(name, value):
    if not isinstance(value, (str, _os.PathLike)):
        raise ValueError(f"{name} must be a path (str or os.PathLike), got {value!r}")
    return _os.fspath(value)


def _sweep_task(text, name, folder, out_dir, index, sweep_id):
    """One task of carom.sweep, on a Dask worker: the plan parsed again from its text (a worker
    needs to see out_dir, not the plan's file), then the task run, or continued from what an
    earlier attempt left, until done or until _stop_sweep_tasks(sweep_id). Returns (status,
    error). Whatever fails here is the task's failure, as `carom sweep` records it (a task lock
    that cannot be made, say), not the whole sweep's."""
    try:
        return _carom.run_task(_carom.SweepPlan.parse(text, name, folder), index, out_dir, sweep_id)
    except Exception as error:
        return "failed", str(error)


def _stop_sweep_tasks(sweep_id):
    """On a Dask worker: stops the tasks of the sweep `sweep_id`, running or to come (each saves
    its checkpoint)."""
    _carom.stop_tasks(sweep_id)


def _typed(text, kind):
    """A swept value as results.csv writes it, as the plan types it (like `kind`)."""
    if isinstance(kind, bool):
        return text == "true"
    if isinstance(kind, list):
        return [float(x) for x in text.split()]
    return type(kind)(text)


def _results_table(plan, path):
    """results.csv as a pandas DataFrame, or as a numpy structured array without pandas: the swept
    keys typed as in the plan, status and error as text, every measure a float (NaN: none)."""
    # A task's error may name a file whose name is not UTF-8: read as os.fsdecode would.
    with open(path, newline="", encoding="utf-8", errors="surrogateescape") as f:
        header, *rows = list(_csv.reader(f))
    first = plan.points[0]
    columns = {}
    for k, name in enumerate(header):
        texts = [row[k] for row in rows]
        if name in first:
            values = [_typed(text, first[name]) for text in texts]
            if isinstance(first[name], list):
                column = _np.empty(len(values), dtype=object)
                column[:] = values
            else:
                column = _np.array(values)
        elif name in ("status", "error"):
            column = _np.array(texts, dtype=str)
        else:
            column = _np.array([float(text) if text else _np.nan for text in texts])
        columns[name] = column
    try:
        import pandas
    except ImportError:
        table = _np.empty(len(rows), dtype=[(name, c.dtype) for name, c in columns.items()])
        for name, column in columns.items():
            table[name] = column
        return table
    return pandas.DataFrame(columns)


def sweep(plan, out_dir, client=None):
    """`carom sweep PLAN -o OUT_DIR` with its tasks handed out by Dask: the same folder, the same
    files, byte for byte, and its results.csv as a table.

    plan: a plan file (TOML), as `carom sweep` reads it (`carom sweep --help` describes it): a
    [start], a [run] or a [compress], and the [sweep] axes whose every combination is a task. A
    bad plan raises ValueError naming the file, line and key, before anything runs; so does an
    out_dir whose task folders hold another plan's tasks, an out_dir that cannot be a folder (a
    file), an out_dir whose files would overwrite the plan or a start file, and an out_dir
    another sweep is running in (its sweep.lock held).

    Each task not yet done is a Dask task (pure=False) that runs it in out_dir/<task>/ exactly as
    `carom sweep` would, on whatever worker gets it: workers must see out_dir and a start `file`
    the plan names (relative paths are taken from each worker's working folder: give absolute
    ones on a shared file system for a cluster), not the plan itself.

    client: a dask.distributed Client; None makes a LocalCluster of one single-threaded worker
    process per core, closed at the end. The tasks are resumable, as
    `carom sweep`'s are: a worker that dies mid-task has the task rerun by Dask elsewhere (the
    scheduler's allowed-failures), continuing it from its checkpoint. Ctrl-C stops the sweep's
    tasks on the workers too (each saves its checkpoint) and raises KeyboardInterrupt once none
    runs any more; called again, by carom.sweep or `carom sweep`, the sweep runs only what is not
    done. A task holds its folder's task.lock while it runs, so that no two ever write one task
    (a task still held, by a worker of an earlier sweep, is waited for). A task that fails (a
    start its options cannot make, a compression that jams short of its `phi`) raises nothing:
    its row says status "failed" and why.

    Then out_dir/results.csv, summary.csv and report.html are written, as `carom sweep` writes
    them, and results.csv is returned: a pandas DataFrame (a numpy structured array without
    pandas), a row a task in the plan's order, with the swept keys as the plan types them, status
    ("done", "failed"), the measures as floats (NaN: not measured) and the error.
    """
    plan = _file_name("plan", plan)
    # The library is given the folder's bytes: its name need not be UTF-8.
    out_dir = _os.fsencode(_file_name("out_dir", out_dir))
    import distributed  # here: only a sweep needs Dask, which takes a second to import
    if client is not None and not isinstance(client, distributed.Client):
        raise ValueError(f"client must be a dask.distributed Client or None, got {client!r}")
    core = _carom.SweepPlan.read(_os.fsencode(plan))
    _carom.check_sweep_folder(core, out_dir)
    _os.makedirs(out_dir, exist_ok=True)
    # No other sweep (carom.sweep, carom sweep or carom_mpi) runs in out_dir meanwhile.
    with _carom.lock_sweep_folder(out_dir):
        waiting = [i for i, result in enumerate(_carom.read_task_results(core, out_dir))
                   if result.status != "done"]
        if waiting:
            if client is None:
                with distributed.LocalCluster(n_workers=_os.cpu_count() or 1,
                                              threads_per_worker=1, processes=True) as cluster, \
                        distributed.Client(cluster) as own:
                    returned = _run_tasks(own, core, out_dir, waiting)
            else:
                returned = _run_tasks(client, core, out_dir, waiting)
        results = _carom.read_task_results(core, out_dir)
        if waiting:
            # What the workers returned, as `carom sweep` keeps what its tasks returned, so that
            # results.csv is the same whatever ran them: a failure that never reached error.txt
            # included. A task's folder, where it agrees, gives its measures too.
            for index, (status, error) in zip(waiting, returned):
                if (results[index].status, results[index].error) != (status, error):
                    results[index] = _carom.TaskResult(status, _os.fsencode(error))
        _carom.write_sweep_tables(core, out_dir, results)
        _carom.write_sweep_report(core, results, _os.path.join(out_dir, b"report.html"))
    return _results_table(core, _os.path.join(out_dir, b"results.csv"))


def _run_tasks(client, plan, out_dir, indices):
    """The tasks `indices` of plan on client's workers, until every one has returned: what each
    returned, (status, error)."""
    sweep_id = _uuid.uuid4().hex
    futures = []
    try:
        for i in indices:
            futures.append(client.submit(_sweep_task, plan.text, plan.name, plan.folder, out_dir, i,
                                         sweep_id, pure=False))
        return client.gather(futures)
    except BaseException:
        # Stopped (Ctrl-C, while the tasks are submitted too) or refused. A cancelled future does
        # not stop a task a worker runs, so every worker is told to stop this sweep's tasks (each
        # saves its checkpoint), nothing is left queued on a client that outlives the sweep, and
        # the sweep returns once every task has let go of its folder: a sweep run again at once
        # finds them free.
        # A worker that cannot be reached (dead, restarting) is skipped: the wait below still
        # waits for any task it holds.
        client.run(_stop_sweep_tasks, sweep_id, on_error="ignore")
        client.cancel(futures)
        _carom.wait_for_tasks(plan, out_dir, indices)
        raise
