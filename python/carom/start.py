"""The Simulations a start makes: carom.read (a file), carom.init (`carom init`'s options) and
carom.resume (a checkpoint)."""

from . import _carom
from ._arguments import _given, _keywords, _path
from .simulation import Simulation


@_keywords(_carom.StartSpec, "path")
def read(path, **options):
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
    spec = _carom.StartSpec(path=path, **_given(options))
    return Simulation._wrap(_carom.Simulation.read(spec))


@_keywords(_carom.InitSpec, "n", "phi")
def init(n, phi, **options):
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
    return Simulation._wrap(_carom.Simulation.init(_carom.InitSpec(n=n, phi=phi, **options)))


def resume(path):
    """The Simulation a checkpoint holds (sim.save or `carom run --checkpoint`), to run on exactly."""
    return Simulation._wrap(_carom.Simulation.resume(_path(path)))
