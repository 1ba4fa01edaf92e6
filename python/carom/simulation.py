"""carom.Simulation, a run held in Python, and carom.compress, which makes one from another."""

import json as _json
import warnings as _warnings

import numpy as _np

from . import _carom
from ._arguments import (_D, _flag, _float_array, _given, _keywords, _number, _path,
                         _per_particle, _species)


class UnsettledWarning(UserWarning):
    """Z did not settle over a measurement window: it drifted between the window's halves, or
    its blocks are correlated, so that its standard error understates the uncertainty. Raised
    where `carom run` and `carom sweep` print "carom: warning: ..." of Z; silenced as any
    warning is: warnings.simplefilter("ignore", carom.UnsettledWarning)."""


class Simulation:
    """A run of hard disks (dim 2) or spheres (dim 3): its state, its engine and its measurement.

    positions, velocities: (N, D) float64 arrays at t = 0 (D = 2 or 3); box: the D sides (the box
    is [0, Lx] x [0, Ly] [x [0, Lz]]); radii, masses: a number or an (N,) array. boundary:
    "walls" (hard walls on every face) or "periodic". rule: "elastic" (momentum exchanged along
    the line of centres, with masses: real hard particles) or "swap" (the classic assignment's:
    touching particles exchange whole velocities); restitution < 1 makes elastic collisions inelastic, and a particle that
    collided less than `tc` ago collides elastically (the TC model against inelastic collapse).
    engine: "fast" (O(1) per event) or "reference" (the classic assignment's O(N^2) algorithm, for checking).
    sampler: "md" (dynamics) or "ecmc" (event-chain Monte Carlo: equilibrium positions at kT = 1 in
    a periodic box; velocities are ignored and masses must be 1), with chain_length (in mean
    diameters; 0: 0.24 of the box's side) and seed (of the chains' particles).

    The start is checked as `carom run` checks a file: finite numbers, positive radii and
    masses, particles inside the box, clear of the walls and of each other (touching is fine);
    anything else is a ValueError saying what and which particle.

    types, typeid: the particles' species, as sim.types and sim.typeid give them back: the names
    (letters, digits, _ . + or -; each once) and each particle's index into them, an (N,) array
    of integers. Without them every particle is of one type, "A"; typeid may be left out for one
    name.

    carom.read, carom.init and carom.resume make Simulations from a file, from `carom init`'s
    options, and from a checkpoint.
    """

    def __init__(self, positions, velocities, box, radii=_D["radius"], masses=_D["mass"],
                 boundary=_D["boundary"], rule=_D["rule"], restitution=_D["restitution"],
                 tc=_D["tc"], engine=_D["engine"], sampler=_D["sampler"],
                 chain_length=_D["chain_length"], seed=_D["seed"], types=None, typeid=None):
        positions = _float_array("positions", positions)
        if positions.ndim != 2 or positions.shape[1] not in (2, 3) or positions.shape[0] < 1:
            raise ValueError(f"positions must have shape (N, 2) or (N, 3) with N >= 1, "
                             f"got {positions.shape}")
        n, d = positions.shape
        velocities = _float_array("velocities", velocities, (n, d))
        box = _float_array("box", box, (d,))
        radii = _per_particle("radii", radii, n, _D["radius"])
        masses = _per_particle("masses", masses, n, _D["mass"])
        types, typeid = _species(types, typeid, n)
        self._running = False
        self._warned = set()
        self._core = _carom.Simulation.from_arrays(
            positions, velocities, box, radii, masses, types, typeid, boundary, rule,
            _number("restitution", restitution), _number("tc", tc), engine, sampler,
            _number("chain_length", chain_length), seed)

    @classmethod
    def _wrap(cls, core):
        simulation = cls.__new__(cls)
        simulation._running = False
        simulation._warned = set()
        simulation._core = core
        return simulation

    @property
    def _idle(self):
        """The engine, when no run is under way (in another thread, with the GIL released)."""
        if self._running:
            raise RuntimeError("this simulation is running (in another thread): wait for run()")
        return self._core

    @_keywords(_carom.RunSpec, "self", "t", collisions=False)
    def run(self, t, collisions=False, **options):
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
        final: the state at t as a start file that carom.read and `carom run` read back to the
        last bit: ".gsd" (one GSD frame; carom's double-precision copies ride beside HOOMD's
        single-precision chunks) or any other name for carom's start format.
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
        Where Z drifted over the measurement window, or its blocks are correlated, the run says
        so with a carom.UnsettledWarning in `carom run`'s words, once a window: the runs after
        it that extend the same window say nothing more of the same (sim.observables() holds
        the verdict), until reset_measurement, measure_from or equilibrate opens another.
        """
        return self._run(t, collisions, options)

    def _run(self, t, collisions, options):
        """run() for run() and advance(): the warnings name their caller's caller's line."""
        options = _given(options)
        if "check_every" in options and not options.get("check"):
            raise ValueError("check_every needs check=True")
        spec = _carom.RunSpec(t=t, **options)
        core = self._idle
        self._running = True
        try:
            unsettled = core.run(spec, _flag("collisions", collisions))
        finally:
            self._running = False
        if "equilibrate" in options:  # a window opened anew
            self._warned.clear()
        for kind, message in unsettled:
            if kind not in self._warned:
                self._warned.add(kind)
                _warnings.warn(message, UnsettledWarning, stacklevel=3)
        return core.collisions() if collisions else None

    def advance(self, dt, **options):
        """Runs for dt more time units, as sim.run(sim.time + dt, ...) (HOOMD's sim.run(steps)).
        The end time is the double sim.time + dt, so many small advances can land a hair off
        round times; run(t) names a time exactly. The options are run()'s."""
        dt = _number("dt", dt)
        if not dt >= 0.0:
            raise ValueError(f"dt must be >= 0, got {dt}")
        return self._run(self.time + dt, options.pop("collisions", False), options)

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
    def sampler(self):
        """"md" (dynamics) or "ecmc" (event chains)."""
        return self._idle.sampler

    @property
    def chain_length(self):
        """Event chains: each chain's length in mean diameters; None for dynamics."""
        return self._idle.chain_length

    @property
    def rule(self):
        """"elastic" (momentum exchanged along the line of centres, with masses) or "swap" (the
        classic assignment's: whole velocities exchanged); None for event chains, as are
        restitution, tc and engine."""
        return self._idle.rule

    @property
    def restitution(self):
        """The coefficient of normal restitution: 1 elastic, below 1 inelastic (granular); None
        for event chains."""
        return self._idle.restitution

    @property
    def tc(self):
        """The TC model's time: a particle that collided less than tc ago collides elastically
        (against inelastic collapse; no effect at restitution 1); None for event chains."""
        return self._idle.tc

    @property
    def engine(self):
        """"fast" (neighbour lists or cells and an event calendar) or "reference" (every pair
        checked after every event: O(N^2), for checking); both give the same events, bit for
        bit. None for event chains."""
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
        """Every particle's velocity at sim.time: (N, D) float64 (a copy); zero under event
        chains, which sample positions."""
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
    def typeid(self):
        """Each particle's type, an index into sim.types: (N,) uint32 (HOOMD's typeid)."""
        return self._idle.typeid

    @property
    def types(self):
        """The names of the particles' types: ["A"] unless the start names more (a mixture of
        carom.init(species=...), a start file's types=, a GSD file's particles/types)."""
        return self._idle.types

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
        self._warned.clear()

    def measure_from(self, t):
        """Opens the measurement window at time t (as `carom run --equilibrate t`)."""
        self._idle.measure_from(_number("measure_from", t))
        self._warned.clear()

    def format(self, kind="table"):
        """The command line's output at sim.time: "table", "csv" or "json" (with particles)."""
        return self._idle.text(kind)

    def save(self, path):
        """Writes a checkpoint (atomically) that carom.resume and `carom run --resume` continue."""
        self._idle.save(_path(path))

    def __repr__(self):
        kind = "disks" if self.dim == 2 else "spheres"
        if self.sampler == "ecmc":
            return (f"<carom.Simulation: {self.n} {kind}, t = {self.time}, {self.events} lifts, "
                    f"{self.boundary}, event chains of {self.chain_length:.6g} diameters>")
        return (f"<carom.Simulation: {self.n} {kind}, t = {self.time}, {self.events} events, "
                f"{self.boundary}, {self.rule}>")


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
