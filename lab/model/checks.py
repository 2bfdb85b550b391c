"""What a user's own functions return, checked before the lab computes with it: the derivatives of a
:class:`lab.ParametricSurface` and the maps of a :class:`lab.ReparametrizedSurface` (issue 35: None, a wrong shape or
text from a user's function is named as such, not met later as numpy's IndexError or an AttributeError)."""

import numpy as np

from ..geometry import validation as _v
from ..geometry.derivatives import Derivatives

__all__ = ["checked_derivatives", "map_values"]


def checked_derivatives(d, shape, name):
    """What a user's ``derivatives(u, v)`` returned, checked: six float arrays of shape ``shape + (3,)``."""
    wanted = f"a Derivatives of six arrays of shape {shape + (3,)} (b, bu, bv, buu, buv, bvv)"
    if not isinstance(d, tuple) or len(d) != 6:
        raise TypeError(f"{name}: derivatives(u, v) must return {wanted}; got {type(d).__name__} "
                        f"{_v._short(d, 60)}")
    fields = []
    for field_name, x in zip(Derivatives._fields, d):
        try:
            arr = np.asarray(x)
            ok = arr.dtype.kind in "biuf"
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise TypeError(f"{name}: derivatives(u, v) must return {wanted}; its {field_name} is "
                            f"{type(x).__name__} {_v._short(x, 60)}")
        if arr.shape != shape + (3,):
            try:
                arr = np.broadcast_to(arr, shape + (3,))
            except ValueError:
                raise ValueError(f"{name}: derivatives(u, v) must return {wanted}; its {field_name} has shape "
                                 f"{arr.shape}") from None
        fields.append(arr.astype(float, copy=False))
    return Derivatives(*fields)


def map_values(func, t, name):
    """``func(t)`` of a reparametrisation checked: three float arrays (s, ds, d2s) of the shape of ``t``, finite."""
    t = np.asarray(t, dtype=float)
    out = func(t)
    wanted = f"(s, ds, d2s), three arrays of shape {t.shape}"
    if not isinstance(out, (tuple, list)) or len(out) != 3:
        raise TypeError(f"{name}(t) must return {wanted}; got {type(out).__name__} {_v._short(out, 60)}")
    values = []
    for part, x in zip(("s", "ds", "d2s"), out):
        arr = _v.as_array(x, f"{name}(t)'s {part}", finite=False)
        try:
            arr = np.broadcast_to(arr, t.shape)
        except ValueError:
            raise ValueError(f"{name}(t) must return {wanted}; its {part} has shape {arr.shape}") from None
        values.append(arr)
    if t.size and not np.all(np.isfinite(values[0])):
        raise ValueError(f"{name}(t) must return finite parameters s; got NaN or inf")
    return tuple(values)
