"""Measured, not assumed: how far apart every colour map's colours stay for normal vision and each colour-vision deficiency.

For each map of ``lab.colormaps.COLOR_MAPS`` (and, for comparison, matplotlib's cividis and viridis, which a student
could otherwise pick in the explorer), the smallest CAM02-UCS colour difference ΔE

* between its classes (the classification: all three pairs; Dill's five bands: all ten pairs), or
* between neighbouring colours at −1, −½, 0, ½, 1 for a continuous map (its range set by these values),

for normal vision and simulated protanopia, deuteranopia and tritanopia (Machado, Oliveira & Fernandes 2009, as
implemented by colorspacious), and whether its lightness J' is ordered (monotonic along the map; for a diverging
map rising to 0 and falling after it; for three classes the middle one the lightest or the darkest).  A ΔE of 1
is barely visible, 10 clearly, 40 at a glance.  Goals (issue 33): the readable classification ≥ 40 under every
simulation, the continuous readable maps ≥ 10 with ordered lightness.

The numbers do not depend on the machine or its load (no timing): ``tests/test_cvd.py`` checks that the table in
``docs/students/colour.md`` is this script's output.

Usage: python benchmarks/colors.py
"""

import numpy as np

from lab.geometry import colormaps, vision

#: matplotlib's maps measured beside the lab's (sampled from matplotlib itself).
MATPLOTLIB = ("cividis", "viridis")


def _matplotlib_measure(name):
    """A :class:`lab.vision.MapMeasure` of matplotlib's continuous map ``name`` (at the same five steps)."""
    from matplotlib import colormaps as mpl

    cmap = mpl[name]
    colors = cmap((np.array(vision.STEPS) + 1) / 2)[:, :3]
    dense = cmap(np.linspace(0, 1, 257))[:, :3]
    smallest = {}
    for v in vision.VISIONS:
        seen = vision.simulate(colors, v)
        smallest[v] = float(np.min(vision.delta_e(seen[:-1], seen[1:])))
    return vision.MapMeasure(name, "sequential", colors, smallest, vision.monotonic(vision.lightness(dense)))


def measures():
    """The :class:`lab.vision.MapMeasure` of every map of the lab, then matplotlib's for comparison."""
    found = [vision.measure(name) for name in colormaps.COLOR_MAPS]
    try:
        found += [_matplotlib_measure(name) for name in MATPLOTLIB]
    except ImportError:  # pragma: no cover - matplotlib comes with PyVista
        pass
    return found


def _verdict(m):
    goal = 40 if m.kind == "classes" and colormaps.normalisation(m.name) == "classification" else 10
    return "yes" if m.worst >= goal and m.ordered else "no"


def table():
    """The measurements as a Markdown table (the one in ``docs/students/colour.md``)."""
    head = ("| map | compared | normal | protanopia | deuteranopia | tritanopia | lightness ordered | readable |\n"
            "| --- | --- | ---: | ---: | ---: | ---: | --- | --- |")
    rows = []
    for m in measures():
        what = {"classes": "classes", "sequential": "steps", "diverging": "steps"}[m.kind]
        name = f"`{m.name}`" if m.name in colormaps.COLOR_MAPS else f"{m.name} (matplotlib)"
        cells = " | ".join(f"{m.smallest[v]:.1f}" for v in vision.VISIONS)
        rows.append(f"| {name} | {what} | {cells} | {'yes' if m.ordered else 'no'} | {_verdict(m)} |")
    return "\n".join([head, *rows])


def main():
    print(table())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
