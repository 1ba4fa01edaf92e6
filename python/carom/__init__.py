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
    result = carom.analyze("movie.xyz", equilibrate=50)    # `carom analyze`: g(r), MSD, psi6, q6,
    #   S(k), F_s(k,t)
    table = carom.sweep("eos.toml", "eos")                 # `carom sweep`, its tasks on Dask

Use Debian's interpreter, ``/usr/bin/python3``, which has numpy and which the module is built for.
Bad arguments raise ``ValueError`` with the command line's messages, naming the options as
keywords (``kT=`` where the command line says ``--kT``); a broken file raises
``carom.InputError`` (a ``ValueError``) naming the file and line; a run that cannot go on (jammed
particles) raises ``carom.JamError`` (a ``RuntimeError``); a run or a sweep whose Z did not
settle, or whose blocks are correlated, warns with ``carom.UnsettledWarning`` where the command
line prints a warning. Ctrl-C during ``run`` raises ``KeyboardInterrupt`` within a fraction of a
second and leaves the simulation whole: it can be saved or run on.
"""

from . import _carom
from ._carom import InputError, JamError
from .analysis import analyze
from .dask_sweep import sweep
from .simulation import Simulation, UnsettledWarning, compress
from .start import init, read, resume

__version__ = _carom.__version__
__all__ = ["Simulation", "read", "init", "resume", "compress", "analyze", "sweep", "InputError",
           "JamError", "UnsettledWarning", "__version__"]
