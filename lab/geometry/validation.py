"""Input validation shared by every public entry point.

Each helper checks one kind of argument once and raises a ``ValueError`` or
``TypeError`` whose message says what was expected and what was received, so
that messages are uniform across the library and can be pinned by tests.
"""

import math
import numbers
import os

import numpy as np

__all__ = [
    "MEMORY_FRACTION",
    "as_array",
    "as_broadcast_arrays",
    "as_choice",
    "as_control_net",
    "as_number",
    "as_parameter_vector",
    "as_parameters",
    "as_positive_int",
    "as_weights",
    "available_memory",
    "check_memory",
    "choice_name",
    "format_bytes",
    "format_count",
    "memory_limit",
    "set_memory_limit",
]


#: Largest coordinate of a control net: the fundamental forms hold 4th powers of the derivatives
#: (|b_u x b_v|^2), which overflow past about 1e77; 1e60 leaves room for the degree factors.
COORDINATE_MAX = 1e60
#: Smallest non-zero extent of a control net, for the same reason (underflow below about 1e-77).
EXTENT_MIN = 1e-60
#: Largest ratio of the largest to the smallest weight, and the range of the weights themselves.
WEIGHT_RATIO_MAX, WEIGHT_RANGE = 1e60, (1e-100, 1e100)


def _as_float_array(value, name, copy=True):
    """``value`` as a float array; ``copy=False`` keeps a float64 array (a broadcast view stays a view)."""
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name} must be an array of numbers; got {type(value).__name__} {_short(value)}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):  # ragged nesting
        raise TypeError(f"{name} must be an array of numbers with rows of equal length; got {type(value).__name__} "
                        f"{_short(value)}") from None
    if raw.dtype.kind == "c":
        raise TypeError(f"{name} must be real numbers; got complex values (the imaginary part would be dropped)")
    if raw.dtype.kind not in "biufO" or (raw.dtype.kind == "O" and raw.size > 10**6):
        raise TypeError(f"{name} must be an array of numbers; got an array of {raw.dtype} {_short(value)}")
    if raw.dtype != np.float64 or copy:
        check_memory(8.0 * raw.size, f"{name} as {format_count(raw.size)} floating-point numbers")
    try:
        return raw.astype(float, copy=copy)
    except OverflowError:
        raise ValueError(f"{name} must be finite numbers; got an integer beyond the float range") from None
    except (TypeError, ValueError):  # objects that are not numbers
        raise TypeError(f"{name} must be an array of numbers; got {type(value).__name__} {_short(value)}") from None


def as_array(value, name, *, finite=True):
    """``value`` as a float array (a 0-d array for a number); text, None and complex values are a ``TypeError``,
    NaN or inf (with ``finite``) a ``ValueError``, each naming ``name``."""
    arr = _as_float_array(value, name, copy=False)
    if finite and arr.size and not (np.isfinite(arr.min()) and np.isfinite(arr.max())):  # no temporary array
        raise ValueError(f"{name} must contain only finite numbers; got NaN or inf")
    return arr


def refuse_class(obj, expected):
    """A ``TypeError`` when ``obj`` is a class rather than one of its objects (``lab.BezierSurface`` given where
    ``lab.surfaces.torus()`` was meant), naming ``expected``."""
    if isinstance(obj, type):
        raise TypeError(f"expected {expected}; got the class {obj.__name__} itself (make one first, e.g. "
                        "lab.surfaces.torus())")


def as_direction(value, name):
    """``value`` as a unit 3-vector: a ``TypeError`` for text or None, a ``ValueError`` naming ``name`` for another
    shape, NaN, inf or the zero vector.  Scaled to 1 before it is normalised, so that the length of (1e308, 1e308, 0)
    does not overflow and that of (1e-320, 0, 0) does not underflow to "zero"."""
    d = as_array(value, name, finite=False)
    if d.shape != (3,) or not np.all(np.isfinite(d)):
        raise ValueError(f"{name} must be a direction (x, y, z) of three finite numbers; got {_short(value)}")
    big = float(np.max(np.abs(d)))
    if not big > 0:
        raise ValueError(f"{name} must be a non-zero vector; got {tuple(float(x) for x in d)}")
    d = d / big
    return d / np.linalg.norm(d)


def as_broadcast_arrays(**arrays):
    """The keyword arrays as float arrays broadcast against each other (views), each checked as :func:`as_array`
    without the finiteness check; a ``ValueError`` names them and their shapes if they do not broadcast."""
    found = {name: as_array(value, name, finite=False) for name, value in arrays.items()}
    try:
        return np.broadcast_arrays(*found.values())
    except ValueError:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in found.items())
        raise ValueError(f"{' and '.join(found)} must broadcast against each other; got shapes {shapes}") from None


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
    big = float(np.max(np.abs(arr)))
    if big > COORDINATE_MAX:
        raise ValueError(f"{name} must have coordinates of at most {COORDINATE_MAX:g}, beyond which the fundamental "
                         f"forms overflow (they hold 4th powers of the derivatives); got coordinates up to {big:.3g}: "
                         "scale the net down (curvature scales by the inverse factor)")
    extent = float(np.max(np.ptp(arr.reshape(-1, arr.shape[-1]), axis=0)))
    if 0 < extent < EXTENT_MIN:
        raise ValueError(f"{name} has an extent of only {extent:.3g}; below {EXTENT_MIN:g} the fundamental forms "
                         "underflow to 0 and every point would look degenerate: scale the net up (curvature scales "
                         "by the inverse factor)")
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
    lo, hi = float(w.min()), float(w.max())
    if hi / lo > WEIGHT_RATIO_MAX or lo < WEIGHT_RANGE[0] or hi > WEIGHT_RANGE[1]:
        raise ValueError(f"{name} must lie within a ratio of {WEIGHT_RATIO_MAX:g} and in [{WEIGHT_RANGE[0]:g}, "
                         f"{WEIGHT_RANGE[1]:g}]; got weights from {lo:.3g} to {hi:.3g}: the rational derivatives "
                         "would overflow (multiplying all weights by one factor leaves the surface unchanged)")
    return w


def as_parameters(u, v, domain, *, atol=1e-12):
    """Broadcast ``u`` and ``v`` against each other and check they lie in ``domain``.

    Values within ``atol`` (relative to the domain size) outside the domain are
    clipped onto it, so that rounding in a caller does not raise.
    """
    uu = _as_float_array(u, "u", copy=False)
    vv = _as_float_array(v, "v", copy=False)
    try:
        np.broadcast_shapes(uu.shape, vv.shape)
    except ValueError:
        raise ValueError(f"u and v must broadcast against each other; got shapes {uu.shape} and {vv.shape}") from None
    # checked (and clipped where rounding put them outside) before they are broadcast: a scalar u is clipped alone
    return tuple(np.broadcast_arrays(_in_interval(uu, domain[0], "u", atol), _in_interval(vv, domain[1], "v", atol)))


def as_parameter_vector(t, interval, name, *, atol=1e-12):
    """A 1-D array of parameters in ``interval`` (one side of a grid), checked and clipped as :func:`as_parameters`."""
    arr = _as_float_array(t, name, copy=False)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of parameters (one side of the grid); got shape {arr.shape}")
    return _in_interval(arr, interval, name, atol)


def _in_interval(arr, interval, name, atol):
    """``arr`` checked to be finite and within ``interval`` up to the slack; clipped (a copy) only if it needs it."""
    lo, hi = interval
    if not arr.size:
        return arr
    low, high = arr.min(), arr.max()  # NaN and inf show up here, without a temporary array
    if not (np.isfinite(low) and np.isfinite(high)):
        raise ValueError(f"{name} must be finite; got NaN or inf")
    slack = atol * max(1.0, hi - lo)
    if low < lo - slack or high > hi + slack:
        raise ValueError(f"{name} must lie in the domain [{lo:g}, {hi:g}]; got values in [{low:g}, {high:g}]")
    if low < lo or high > hi:  # the clipped copy: estimated first (a broadcast view may stand for a huge array)
        check_memory(8 * arr.size, f"clipping {format_count(arr.size)} values of {name} onto the domain", None)
        return np.clip(arr, lo, hi)
    return arr


#: The smallest positive normal float: below it (subnormal numbers) 1/x overflows and products lose digits.
TINY = float(np.finfo(float).tiny)


def as_number(value, name, *, positive=False, minimum=None, maximum=None):
    """Return ``value`` as a finite float, checked once for every public number parameter.

    Python and numpy reals (and 0-d real arrays) are accepted; ``bool``,
    strings, ``None`` and complex numbers are a ``TypeError`` naming ``name``,
    NaN, inf and values out of range a ``ValueError``.

    Parameters
    ----------
    positive : bool
        Require ``value > 0`` and a normal float (at least :data:`TINY`, 2.2e-308).
    minimum, maximum : float, optional
        Require ``minimum <= value <= maximum``.
    """
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__} {_short(value)}")
    try:
        x = float(value)
    except OverflowError:  # an int beyond the float range (10**400)
        raise ValueError(f"{name} must be a finite number; got an integer of about {format_count(abs(value))} "
                         "(beyond the float range)") from None
    wanted = "a positive number" if positive else "a finite number"
    if minimum is not None and maximum is not None:
        wanted = f"in [{minimum:g}, {maximum:g}]"
    elif minimum is not None:
        wanted = f">= {minimum:g}"
    elif maximum is not None:
        wanted = f"<= {maximum:g}"
    if not np.isfinite(x) or (positive and not x > 0) or (minimum is not None and x < minimum) or (
            maximum is not None and x > maximum):
        raise ValueError(f"{name} must be {wanted}; got {value!r}")
    if positive and x < TINY:  # a subnormal float: its reciprocal overflows, its products lose their digits
        raise ValueError(f"{name} must be a positive number of at least {TINY:.3g} (the smallest normal float); got "
                         f"{value!r}, a subnormal number whose reciprocal is infinite")
    return x


def _short(value, n=80):
    """``repr(value)``, cut to ``n`` characters (an int too large to print, a long text)."""
    try:
        text = repr(value)
    except ValueError:  # an int beyond Python's limit on digits for printing
        return f"an integer of about {format_count(abs(value))}"
    return text if len(text) <= n else text[: n - 1] + "…"


def as_positive_int(value, name, minimum=0, maximum=None):
    """Return ``value`` as an int >= ``minimum`` (and <= ``maximum``)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer; got {type(value).__name__} {_short(value)}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {_short(value)}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be an integer from {minimum} to {maximum}; got {_short(value)}")
    return int(value)


def as_choice(value, choices, name):
    """Return ``value`` if it is one of ``choices`` (compared with ``==``)."""
    for choice in choices:
        if value == choice:
            return choice
    listed = ", ".join(repr(choice_name(c)) for c in choices)
    raise ValueError(f"unknown {name} {choice_name(value)!r}; expected one of {listed}")


def choice_name(value):
    """The plain name of a choice: an enum member's value (``'gaussian'``, not ``<CurvatureMode.GAUSSIAN: ...>``)."""
    return getattr(value, "value", value)


# ----------------------------------------------------------------------------- memory guard

#: Share of the available memory that one call may plan to use by default.
MEMORY_FRACTION = 0.5
_override = {"limit": None}


def available_memory():
    """Memory this process can still use, in bytes: MemAvailable, lowered by a container's (cgroup) limit.

    None where neither is known.
    """
    found = []
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    found.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError, IndexError):
        pass
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        try:
            with open(limit_file) as f:
                text = f.read().strip()
            with open(usage_file) as f:
                used = int(f.read().strip())
            if text != "max" and int(text) < 2**60:
                found.append(max(int(text) - used, 0))
        except (OSError, ValueError):
            pass
    if not found:
        try:
            found.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (OSError, ValueError, AttributeError):
            return None
    return min(found)


def _as_bytes(value, name="memory limit"):
    units = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}
    if isinstance(value, str):
        text = value.strip().upper().removesuffix("IB").removesuffix("B")
        unit = text[-1:] if text[-1:] in units else ""
        try:
            value = float(text[: len(text) - len(unit)]) * units[unit]
        except ValueError:
            raise ValueError(f"{name} must be a number of bytes or a size such as '2G'; got {value!r}") from None
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not value > 0 or not (
            value < 2**100 and math.isfinite(value)):  # 2**100 first: a huge int does not convert to a float
        raise ValueError(f"{name} must be a positive number of bytes (below 2**100) or a size such as '2G'; got "
                         f"{_short(value)}")
    return int(value)


def format_count(n):
    """A count as a short text, exact up to 10**15, else ``'1.73e+361'`` (even past float range and
    Python's limit on digits for int-to-string conversion)."""
    if n < 10**15:
        return str(int(n))
    exponent = math.log10(n)  # math.log10 takes ints of any size
    return f"{10 ** (exponent % 1):.3g}e+{int(exponent)}"


def format_bytes(n):
    """``n`` bytes as a short text: ``'1.5 GiB'``."""
    if n >= 2**60:  # beyond a million TiB; n / size of a huge int would overflow a float
        return f"{format_count(n)} B"
    for unit, size in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def memory_limit():
    """The memory one call may plan to use, in bytes, and where that number comes from.

    In this order: :func:`set_memory_limit`, the environment variable
    ``LAB_MEMORY_LIMIT`` (bytes, or a size such as ``"4G"``), else
    :data:`MEMORY_FRACTION` of :func:`available_memory` (looked up at each call).

    Returns
    -------
    (int, str)
    """
    if _override["limit"] is not None:
        return _override["limit"], "set with lab.set_memory_limit"
    env = os.environ.get("LAB_MEMORY_LIMIT")
    if env:
        return _as_bytes(env, "LAB_MEMORY_LIMIT"), "from LAB_MEMORY_LIMIT"
    available = available_memory()
    if available is None:
        return 4 * 2**30, "a default of 4 GiB: the available memory is unknown"
    return int(MEMORY_FRACTION * available), f"{MEMORY_FRACTION:.0%} of the {format_bytes(available)} available"


def set_memory_limit(limit):
    """Set the memory one call may plan to use (bytes, or a size such as ``"8G"``); ``None`` restores the default.

    Returns the previous setting (None for the default), so that a test or a
    course hub can restore it.
    """
    previous = _override["limit"]
    _override["limit"] = None if limit is None else _as_bytes(limit)
    return previous


def check_memory(nbytes, what, limit=None):
    """Refuse work whose estimated memory ``nbytes`` exceeds the limit, before anything is allocated.

    Parameters
    ----------
    nbytes : float
        Estimated peak memory of the work, in bytes.
    what : str
        The work, for the message (``"refine(14) (13153337344 patches)"``).
    limit : int or str, optional
        Overrides :func:`memory_limit` for this call.

    Raises
    ------
    ValueError
        Naming the estimate and the limit.
    """
    if limit is None:
        limit, source = memory_limit()
    else:
        limit, source = _as_bytes(limit), "given as memory_limit"
    if nbytes > limit:
        raise ValueError(
            f"{what} would need about {format_bytes(nbytes)} of memory, more than the limit of "
            f"{format_bytes(limit)} ({source}); ask for less, or, if the machine has the memory, raise the limit "
            "with lab.set_memory_limit(...), the environment variable LAB_MEMORY_LIMIT or the call's memory_limit "
            "keyword where it has one"
        )
