"""The Simulations a start makes: carom.read (a file), carom.init (`carom init`'s options) and
carom.resume (a checkpoint)."""

from . import _carom
from ._arguments import (_BOUNDARIES, _D, _ENGINES, _RULES, _choice, _flag, _float_array,
                         _number, _path, _whole)
from .simulation import Simulation


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


def resume(path):
    """The Simulation a checkpoint holds (sim.save or `carom run --checkpoint`), to run on exactly."""
    return Simulation._wrap(_carom.Simulation.resume(_path(path)))
