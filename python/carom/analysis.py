"""carom.analyze: `carom analyze` of a trajectory, its result as numpy arrays."""

import json as _json

import numpy as _np

from . import _carom
from ._arguments import _number, _path


def _positive(name, value):
    """None (the default) as 0, else a number greater than 0."""
    if value is None:
        return 0.0
    value = _number(name, value)
    if not value > 0:
        raise ValueError(f"{name} must be greater than 0, not {value}")
    return value


def analyze(trajectory, equilibrate=None, bin=None, r_max=None, contact_width=None, log=None,
            html=None, k_max=None, fs_k=None):
    """`carom analyze` on a .gsd or .xyz trajectory: a dict of its JSON, arrays as numpy arrays.

    Keys: "rdf" (r, g, bin_width, r_max, contact: {r, g, Z} or None, and for a trajectory of two
    types or more partial: {"A-B": g_AB(r), ...} and partial_weights: {"A-B": share of pairs},
    sum share x g_AB = g), "msd" (t, msd) or None,
    "psi6" (t, global, local_mean) or None, "structure_factor" (k, s, k_peak) or None,
    "self_scattering" (k, t, fs, alpha2 (NaN at t = 0), tau_alpha or None) or None, "snapshot"
    (the last frame's positions, an (N, D) array, radii, and local psi6 as psi6_modulus and
    psi6_phase), "time", "packing_fraction", "warnings" (why an analysis is absent), ... Frames
    before `equilibrate` are left out; bin (default d / 50), r_max (5 d), contact_width (d / 10),
    k_max (20 / d) and fs_k (the main peak of S(k)) are the command's --bin, --r-max,
    --contact-width, --k-max and --fs-k. `log` adds a `carom run --log` table to the result and
    the page; `html` writes the report page there. A broken file raises carom.InputError, bad
    options ValueError.
    """
    result = _json.loads(_carom.analyze(
        _path(trajectory), -1e300 if equilibrate is None else _number("equilibrate", equilibrate),
        _positive("bin", bin), _positive("r_max", r_max),
        _positive("contact_width", contact_width), _positive("k_max", k_max),
        _positive("fs_k", fs_k), None if log is None else _path(log),
        None if html is None else _path(html)))
    arrays = {"rdf": ("r", "g"), "msd": ("t", "msd"), "psi6": ("t", "global", "local_mean"),
              "structure_factor": ("k", "s"), "self_scattering": ("t", "fs", "alpha2"),
              "snapshot": ("radius", "psi6_modulus", "psi6_phase")}
    for section, keys in arrays.items():
        for key in keys:
            if result[section] is not None and result[section][key] is not None:
                result[section][key] = _np.array(result[section][key], dtype=_np.float64)
    # A mixture's partial g_ab(r), by pair name ("A-B").
    for name, values in result["rdf"].get("partial", {}).items():
        result["rdf"]["partial"][name] = _np.array(values, dtype=_np.float64)
    snapshot = result["snapshot"]
    snapshot["position"] = _np.array(snapshot["position"], dtype=_np.float64).reshape(
        -1, result["dimension"])
    result["time"] = _np.array(result["time"], dtype=_np.float64)
    return result
