"""Input validation shared by every public entry point.

Each helper checks one kind of argument once and raises a ``ValueError`` or
``TypeError`` whose message says what was expected and what was received, so
that messages are uniform across the library and can be pinned by tests.
"""

import numbers

import numpy as np

__all__ = [
    "as_control_net",
    "as_weights",
    "as_parameters",
    "as_positive_int",
    "as_choice",
]


def _as_float_array(value, name):
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be an array of numbers; got {type(value).__name__}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be an array of numbers; got {type(value).__name__} ({exc})") from None
    return arr


def as_control_net(P, name="control net", batch=False, dim=3):
    """Return ``P`` as a float array of shape ``(..., m+1, n+1, dim)``.

    Parameters
    ----------
    P : array_like
        Control net. With ``batch=False`` exactly ``(m+1, n+1, dim)``; with
        ``batch=True`` any number of leading batch axes is allowed.
    name : str
        Used in error messages.
    batch : bool
        Whether leading batch axes are allowed.
    dim : int or None
        Required size of the last axis; ``None`` accepts any size >= 1.
    """
    arr = _as_float_array(P, name)
    shape_txt = f"(m+1, n+1, {dim if dim is not None else 'd'})"
    if batch:
        shape_txt = "(..., " + shape_txt[1:]
    ok_ndim = arr.ndim >= 3 if batch else arr.ndim == 3
    if not ok_ndim or (dim is not None and arr.shape[-1] != dim) or 0 in arr.shape:
        raise ValueError(f"{name} must have shape {shape_txt}; got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite values; got NaN or inf")
    return arr


def as_weights(weights, shape, name="weights"):
    """Return positive finite ``weights`` of exactly ``shape`` (or ``None``)."""
    if weights is None:
        return None
    w = _as_float_array(weights, name)
    if w.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} (one per control point); got {w.shape}")
    if not np.all(np.isfinite(w)):
        raise ValueError(f"{name} must contain only finite values; got NaN or inf")
    if np.any(w <= 0):
        raise ValueError(f"{name} must be positive; got minimum {w.min():g}")
    return w


def as_parameters(u, v, domain, *, atol=1e-12):
    """Broadcast ``u`` and ``v`` against each other and check they lie in ``domain``.

    Values within ``atol`` (relative to the domain size) outside the domain are
    clipped onto it, so that rounding in a caller does not raise.
    """
    uu = _as_float_array(u, "u")
    vv = _as_float_array(v, "v")
    try:
        uu, vv = np.broadcast_arrays(uu, vv)
    except ValueError:
        raise ValueError(f"u and v must broadcast against each other; got shapes {uu.shape} and {vv.shape}") from None
    out = []
    for name, arr, (lo, hi) in (("u", uu, domain[0]), ("v", vv, domain[1])):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite; got NaN or inf")
        slack = atol * max(1.0, hi - lo)
        if arr.size and (arr.min() < lo - slack or arr.max() > hi + slack):
            raise ValueError(
                f"{name} must lie in the domain [{lo:g}, {hi:g}]; got values in [{arr.min():g}, {arr.max():g}]"
            )
        out.append(np.clip(arr, lo, hi))
    return out[0], out[1]


def as_positive_int(value, name, minimum=0):
    """Return ``value`` as an int >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer; got {type(value).__name__} {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value}")
    return int(value)


def as_choice(value, choices, name):
    """Return ``value`` if it is one of ``choices`` (compared with ``==``)."""
    for choice in choices:
        if value == choice:
            return choice
    listed = ", ".join(repr(c) for c in choices)
    raise ValueError(f"unknown {name} {value!r}; expected one of {listed}")
