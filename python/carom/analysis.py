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


# The Steinhardt bond order's invariants, under their JSON names: per frame (their means) in
# result["steinhardt"], per particle in result["steinhardt"]["last_frame"].
_INVARIANTS = tuple(f"{kind}{l}{bar}" for l in (4, 6) for kind in "qw" for bar in ("", "_bar"))


def _selection(only):
    """None (every analysis), or the names as one comma-separated string for the library."""
    if only is None:
        return None
    names = [only] if isinstance(only, str) else list(only)
    if not names or not all(isinstance(name, str) for name in names) or \
            (not isinstance(only, str) and any("," in name for name in names)):
        raise ValueError(f"only must name analyses (a name, a comma-separated string of them or "
                         f"a list of names), not {only!r}")
    return ",".join(names)


def analyze(trajectory, equilibrate=None, bin=None, r_max=None, contact_width=None, log=None,
            html=None, k_max=None, fs_k=None, order_cutoff=None, com=False, only=None):
    """`carom analyze` on a .gsd or .xyz trajectory: a dict of its JSON, arrays as numpy arrays.

    Keys: "rdf" (r, g, bin_width, r_max, contact: {r, g, Z} or None, and for a trajectory of two
    types or more partial: {"A-B": g_AB(r), ...} and partial_weights: {"A-B": share of pairs},
    sum share x g_AB = g), "msd" (t, msd, self_diffusion, centre_of_mass_shift,
    from_centre_of_mass) or None,
    "psi6" (t, global, local_mean, orientation: the global order's bond angle to the x axis in
    degrees, in (-30, 30]) or None (spheres), "steinhardt" or None (disks): per frame t,
    the means q4, q6, w4, w6, q4_bar, q6_bar, w4_bar, w6_bar, the counts solid_like and
    largest_cluster, cluster_sizes (an array a frame, largest first), and last_frame (each
    particle's neighbours, q4 ... w6_bar, solid_bonds, solid_like and cluster, -1 if none);
    "structure_factor" (k, s, k_peak) or None, "self_scattering" (k, t, fs, alpha2 (NaN at
    t = 0), tau_alpha or None) or None; "snapshot" (the last frame's positions, an (N, D) array,
    radii, and local psi6 as psi6_modulus and psi6_phase), "time", "packing_fraction",
    "warnings" (why an analysis is absent), ... Frames before `equilibrate` are left out; bin
    (default d / 50), r_max (5 d), contact_width (d / 10), k_max (20 / d), fs_k (the main peak of
    S(k)) and order_cutoff (1.5 d) are the command's --bin, --r-max, --contact-width, --k-max,
    --fs-k and --order-cutoff; com=True is its --com (the MSD and F_s(k,t) from displacements
    relative to the centre of mass, which event chains move). only: the analyses to compute, by
    their keys here ("psi6", or ["rdf", "structure_factor"]: the others are None, and
    result["only"] lists those asked for), as the command's --only; every one by default
    (result["only"] None). `log` adds a `carom run --log` table to the result and the page;
    `html` writes the report page there. A broken file raises carom.InputError, bad options
    ValueError.
    """
    result = _json.loads(_carom.analyze(
        _path(trajectory), -1e300 if equilibrate is None else _number("equilibrate", equilibrate),
        _positive("bin", bin), _positive("r_max", r_max),
        _positive("contact_width", contact_width), _positive("k_max", k_max),
        _positive("fs_k", fs_k), _positive("order_cutoff", order_cutoff), bool(com),
        None if log is None else _path(log), None if html is None else _path(html),
        _selection(only)))
    arrays = {"rdf": ("r", "g"), "msd": ("t", "msd"),
              "psi6": ("t", "global", "local_mean", "orientation"),
              "structure_factor": ("k", "s"), "self_scattering": ("t", "fs", "alpha2"),
              "snapshot": ("radius", "psi6_modulus", "psi6_phase"),
              "steinhardt": ("t",) + _INVARIANTS}
    for section, keys in arrays.items():
        for key in keys:
            if result[section] is not None and result[section][key] is not None:
                result[section][key] = _np.array(result[section][key], dtype=_np.float64)
    # A mixture's partial g_ab(r), by pair name ("A-B").
    for name, values in (result["rdf"] or {}).get("partial", {}).items():
        result["rdf"]["partial"][name] = _np.array(values, dtype=_np.float64)
    order = result["steinhardt"]
    if order is not None:
        for key in ("solid_like", "largest_cluster"):
            order[key] = _np.array(order[key], dtype=_np.int64)
        order["cluster_sizes"] = [_np.array(s, dtype=_np.int64) for s in order["cluster_sizes"]]
        last = order["last_frame"]
        for key in _INVARIANTS:
            last[key] = _np.array(last[key], dtype=_np.float64)
        for key in ("neighbours", "solid_bonds", "cluster"):
            last[key] = _np.array(last[key], dtype=_np.int64)
        last["solid_like"] = _np.array(last["solid_like"], dtype=bool)
    snapshot = result["snapshot"]
    snapshot["position"] = _np.array(snapshot["position"], dtype=_np.float64).reshape(
        -1, result["dimension"])
    result["time"] = _np.array(result["time"], dtype=_np.float64)
    return result
