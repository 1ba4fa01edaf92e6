"""The checks of Python arguments the library cannot make (types, shapes, numpy dtypes), the
forms in which the library takes them, and the signatures of functions that pass keywords on to
the library's requests."""

import inspect as _inspect
import math as _math
import numbers as _numbers
import os as _os

import numpy as _np

from . import _carom

# Every default a signature shows is the library's, read from it here.
_D = _carom.defaults


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


def _species(types, typeid, n):
    """types= and typeid= as the library takes them: a list of names and an (N,) uint32 array.
    The names and the indices' range are the library's to check; here, what it cannot see: a
    list of str (not a str, whose letters would read as names), indices that are not integers or that no
    uint32 holds."""
    if types is None:
        types = ["A"]
    elif not isinstance(types, (list, tuple)) or not all(isinstance(t, str) for t in types):
        raise ValueError(f"types must be a list of names (str), got {types!r}")
    types = list(types)
    if typeid is None:
        if len(types) != 1:
            raise ValueError(f"types names {len(types)} types: typeid= must say which each "
                             f"of the {n} particles is")
        return types, _np.zeros(n, dtype=_np.uint32)
    array = _np.asarray(typeid)
    if array.dtype.kind not in "iu":
        raise ValueError(f"typeid must be an array of integers, got dtype {array.dtype}")
    if array.shape != (n,):
        raise ValueError(f"typeid must have shape ({n},), one type a particle, got {array.shape}")
    beyond = (array < 0) | (array > _np.iinfo(_np.uint32).max)
    if beyond.any():
        i = int(_np.argmax(beyond))
        raise ValueError(f"the type {array[i]} of particle {i} is not the index of one of the "
                         f"{len(types)} types (0 to {len(types) - 1})")
    return types, _np.ascontiguousarray(array, dtype=_np.uint32)


def _number(name, value):
    """A finite float, as the command line reads numbers."""
    if isinstance(value, bool) or not isinstance(value, _numbers.Real):
        raise ValueError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not _math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value}")
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


def _keywords(spec, *leading, **more):
    """Gives the function a signature: its `leading` arguments, then the keywords of the
    library's request `spec` with the defaults a default-made request holds, then `more`."""
    def sign(function):
        shown = {**spec.keywords(), **more}
        parameters = [_inspect.Parameter(name, _inspect.Parameter.POSITIONAL_OR_KEYWORD)
                      for name in leading]
        parameters += [_inspect.Parameter(name, _inspect.Parameter.KEYWORD_ONLY, default=default)
                       for name, default in shown.items() if name not in leading]
        function.__signature__ = _inspect.Signature(parameters)
        return function
    return sign


def _given(options):
    """The options given: None is the default."""
    return {name: value for name, value in options.items() if value is not None}
