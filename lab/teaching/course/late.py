"""The late policy, one for ``gradebook`` (which applies it) and ``feedback`` (which tells a late student what it
costs): ``--late-penalty P`` percent of the points per started day late, after ``--grace`` minutes, at most
``--late-cap`` percent."""

import math

from ...i18n import _

__all__ = ["LatePolicy", "LatePolicyError", "add_late_options", "late_policy"]


class LatePolicyError(ValueError):
    """Options that make no late policy."""


class LatePolicy:
    """``percent`` of the points per started day late, after ``grace`` minutes, at most ``cap`` percent."""

    def __init__(self, percent=0.0, cap=100.0, grace=0.0):
        for name, value, top in (("--late-penalty", percent, 100), ("--late-cap", cap, 100), ("--grace", grace, None)):
            if not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0 or (top and value > top):
                raise LatePolicyError(f"{name} must be a number from 0{f' to {top}' if top else ''}; got {value!r}")
        self.percent, self.cap, self.grace = float(percent), float(cap), float(grace)

    def days(self, late_seconds):
        late = max(0.0, float(late_seconds or 0) - 60 * self.grace)
        return math.ceil(late / 86400) if late > 0 else 0

    def penalty(self, late_seconds):
        """The penalty in percent of the points."""
        return min(self.cap, self.percent * self.days(late_seconds))

    def apply(self, points, late_seconds):
        """``points`` less the penalty, rounded to hundredths as the gradebook shows them."""
        return round(points * (1 - self.penalty(late_seconds) / 100), 2)


def add_late_options(parser, penalty=0.0):
    """The options of a :class:`LatePolicy` (``--late-penalty``, ``--late-cap``, ``--grace``); read them back with
    :func:`late_policy`.  ``penalty=None``: no penalty given (feedback then does not state one)."""
    parser.add_argument("--late-penalty", type=float, default=penalty,
                        help=_("percent of the points per started day late"))
    parser.add_argument("--late-cap", type=float, default=100.0,
                        help=_("largest late penalty in percent (default 100)"))
    parser.add_argument("--grace", type=float, default=0.0, help=_("minutes after the deadline without penalty"))


def late_policy(args):
    """The :class:`LatePolicy` of options added by :func:`add_late_options`, or None without ``--late-penalty``."""
    return None if args.late_penalty is None else LatePolicy(args.late_penalty, args.late_cap, args.grace)
