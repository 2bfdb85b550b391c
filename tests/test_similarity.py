"""curvature-lab similarity (issue 32): planted copies among independently written correct solutions.

Notebook 05: five students wrote visualize_curvature on their own: ada is tests/students.py's correct solution (that
file holds one student's code and its mistakes, one token apart: not independent solutions), ben, cem, dora and eva
(who works in the German notebook) are written here, each in another style, and each passes lab.check's graded run.
Five handed in a copy of one of them (each still passes the checks): fay renamed every variable of ada's, gil put
cem's functions in another order, hal changed dora's comments and added a docstring, ivy reformatted ben's (two-space
indents, no spaces around operators, a call over six lines with a trailing comma), jan took the curvature half of
eva's and wrote the colours himself.  Beside them zoe handed in the reference solution, three notebooks cannot be
read (invalid JSON, a JSON list, a link) and one has a cell of 300 000 characters (cut).  Notebook 04: six students
wrote only the one-line f1 (kim and lea as the reference solution does, max, nia, rob and sue with np.clip), each
their own written answer; "@pia" copied ola's code (renamed) and answer (reworded), sue rewrote rob's answer as a list.

The ranking of notebook 05 (percent, as the page shows it; the same in every run), every pair with a matching stretch:

    ada – fay   100  planted: renamed
    ben – ivy   100  planted: reformatted
    cem – gil   100  planted: reordered
    dora – hal   98  planted: re-commented
    eva – jan    81  planted: partial copy
    ben – eva    13  honest (the if/elif over the four curvature modes)
    eva – ivy    13  honest (ivy is ben's copy)
    ben – jan    11  honest (jan's half of eva's)
    ivy – jan    11  honest
    the other 36 pairs: no stretch of 80 characters, not listed

Notebook 04: @pia – ola 100 (both: code 100, written 45), rob – sue 88 (written); no other pair is listed.

One set-up per module (``course``): both folders built and compared once.
"""

import csv
import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import nbformat
import pytest

from lab import i18n
from lab.teaching.course import similarity
from tests import students

ROOT = Path(__file__).resolve().parent.parent
ID05, ID04 = "05_visualize_curvature", "04_color_maps"

BEN = '''
import math

import numpy as np

from lab.colormaps import f1, f2, f3, h


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        # curvature at the four corners of each patch
        found = []
        for pt in self:
            net = np.asarray(pt.control_points, dtype=float)
            p, q = pt.degree
            d_u = p * np.diff(net, axis=0)
            d_v = q * np.diff(net, axis=1)
            d_uu = p * (p - 1) * np.diff(net, n=2, axis=0)
            d_vv = q * (q - 1) * np.diff(net, n=2, axis=1)
            d_uv = p * q * np.diff(np.diff(net, axis=0), axis=1)
            here = []
            for r, c in [(0, 0), (0, -1), (-1, 0), (-1, -1)]:
                xu, xv = d_u[r, c], d_v[r, c]
                normal = np.cross(xu, xv)
                normal = normal / math.sqrt(np.dot(normal, normal))
                g11, g12, g22 = np.dot(xu, xu), np.dot(xu, xv), np.dot(xv, xv)
                h11, h12, h22 = np.dot(normal, d_uu[r, c]), np.dot(normal, d_uv[r, c]), np.dot(normal, d_vv[r, c])
                det = g11 * g22 - g12 ** 2
                gauss = (h11 * h22 - h12 ** 2) / det
                mean = (h11 * g22 + h22 * g11 - 2 * h12 * g12) / det / 2
                disc = math.sqrt(max(mean ** 2 - gauss, 0))
                if curvature_mode == self.CURVATURE_GAUSSIAN:
                    here.append(gauss)
                elif curvature_mode == self.CURVATURE_AVERAGE:
                    here.append(mean)
                elif curvature_mode == self.CURVATURE_PRINCIPAL_MAX:
                    here.append(mean + disc)
                else:
                    here.append(mean - disc)
            pt.set_curvature(here[0], here[1], here[2], here[3])
            found += here
        # colours
        pts = self.control_points.reshape(-1, 3)
        diag = float(np.linalg.norm(np.ptp(pts, axis=0)))
        eps = 1e-9 / (diag ** 2 if curvature_mode == self.CURVATURE_GAUSSIAN else diag)
        lo, hi = min(found), max(found)
        if hi - lo <= eps:
            lo = hi

        def colour(val):
            if color_map == self.COLOR_MAP_CUT:
                return h(f1(val))
            if color_map == self.COLOR_MAP_LINEAR:
                return h(f2(val, lo, hi))
            return h(f3(val, eps))

        for pt in self:
            a, b, c, d = (tuple(colour(v)) for v in pt.curvature.ravel())
            pt.set_colors(a, b, c, d)
'''

CEM = '''
import math

import numpy as np

from lab.colormaps import f1, f2, f3, h


def corner_frame(net, m, n, a, b):
    """First and second derivatives of the patch at the corner (a, b), a and b in {0, 1}."""
    i = 0 if a == 0 else m - 1
    j = 0 if b == 0 else n - 1
    k = 0 if a == 0 else m - 2
    l = 0 if b == 0 else n - 2
    row = 0 if a == 0 else m
    col = 0 if b == 0 else n
    su = m * (net[i + 1][col] - net[i][col])
    sv = n * (net[row][j + 1] - net[row][j])
    suu = m * (m - 1) * (net[k + 2][col] - 2 * net[k + 1][col] + net[k][col])
    svv = n * (n - 1) * (net[row][l + 2] - 2 * net[row][l + 1] + net[row][l])
    suv = m * n * (net[i + 1][j + 1] - net[i + 1][j] - net[i][j + 1] + net[i][j])
    return su, sv, suu, suv, svv


def fundamental_forms(su, sv, suu, suv, svv):
    nrm = np.cross(su, sv)
    nrm = nrm / np.linalg.norm(nrm)
    first = (float(su @ su), float(su @ sv), float(sv @ sv))
    second = (float(nrm @ suu), float(nrm @ suv), float(nrm @ svv))
    return first, second


def curvature_of(first, second, which, kinds):
    E, F, G = first
    L, M, N = second
    W = E * G - F * F
    gaussian = (L * N - M * M) / W
    mean = (E * N + G * L - 2 * F * M) / (2 * W)
    spread = math.sqrt(max(mean * mean - gaussian, 0.0))
    table = dict(zip(kinds, (gaussian, mean, mean + spread, mean - spread)))
    return table[which]


def tolerance(points, gaussian):
    extent = np.linalg.norm(points.max(axis=0) - points.min(axis=0))
    return 1e-9 / extent ** 2 if gaussian else 1e-9 / extent


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        kinds = (self.CURVATURE_GAUSSIAN, self.CURVATURE_AVERAGE, self.CURVATURE_PRINCIPAL_MAX,
                 self.CURVATURE_PRINCIPAL_MIN)
        everything = []
        for bez in self:
            m, n = bez.degree
            net = bez.control_points
            vals = [curvature_of(*fundamental_forms(*corner_frame(net, m, n, a, b)), curvature_mode, kinds)
                    for a, b in ((0, 0), (0, 1), (1, 0), (1, 1))]
            bez.set_curvature(*vals)
            everything.extend(vals)
        tol = tolerance(self.control_points.reshape(-1, 3), curvature_mode == self.CURVATURE_GAUSSIAN)
        smallest, largest = min(everything), max(everything)
        if largest - smallest <= tol:
            smallest = largest
        pick = {self.COLOR_MAP_LINEAR: lambda x: f2(x, smallest, largest),
                self.COLOR_MAP_CUT: f1,
                self.COLOR_MAP_CLASSIFICATION: lambda x: f3(x, tol)}[color_map]
        for bez in self:
            bez.set_colors(*[tuple(h(pick(x))) for x in bez.curvature.flatten()])
'''

DORA = '''
import math

import numpy as np

from lab.colormaps import f1, f2, f3, h


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        # derivatives of all corners at once, then K and H with einsum
        collected = np.empty((len(self), 4))
        rows, cols = np.array([0, 0, -1, -1]), np.array([0, -1, 0, -1])
        for idx, bp in enumerate(self):
            C = np.array(bp.control_points, dtype=float)
            du_, dv_ = bp.degree
            Tu = du_ * (C[1:, :, :] - C[:-1, :, :])
            Tv = dv_ * (C[:, 1:, :] - C[:, :-1, :])
            Tuu = du_ * (du_ - 1) * (C[2:, :, :] - 2 * C[1:-1, :, :] + C[:-2, :, :])
            Tvv = dv_ * (dv_ - 1) * (C[:, 2:, :] - 2 * C[:, 1:-1, :] + C[:, :-2, :])
            Tuv = du_ * dv_ * (C[1:, 1:, :] - C[:-1, 1:, :] - C[1:, :-1, :] + C[:-1, :-1, :])
            a, b = Tu[rows, cols], Tv[rows, cols]
            nn = np.cross(a, b)
            nn = nn / np.sqrt(np.einsum("ij,ij->i", nn, nn))[:, None]
            EE = np.einsum("ij,ij->i", a, a)
            FF = np.einsum("ij,ij->i", a, b)
            GG = np.einsum("ij,ij->i", b, b)
            LL = np.einsum("ij,ij->i", nn, Tuu[rows, cols])
            MM = np.einsum("ij,ij->i", nn, Tuv[rows, cols])
            NN = np.einsum("ij,ij->i", nn, Tvv[rows, cols])
            den = EE * GG - FF ** 2
            KK = (LL * NN - MM ** 2) / den
            HH = (EE * NN - 2 * FF * MM + GG * LL) / (2 * den)
            dd = np.sqrt(np.clip(HH ** 2 - KK, 0, None))
            if curvature_mode == self.CURVATURE_GAUSSIAN:
                out = KK
            elif curvature_mode == self.CURVATURE_AVERAGE:
                out = HH
            elif curvature_mode == self.CURVATURE_PRINCIPAL_MAX:
                out = HH + dd
            else:
                out = HH - dd
            collected[idx] = out
            bp.set_curvature(*(float(v) for v in out))
        # the colour map over every corner of every patch
        span = np.linalg.norm(np.ptp(self.control_points.reshape(-1, 3), axis=0))
        power = 2 if curvature_mode == self.CURVATURE_GAUSSIAN else 1
        zero = 1e-9 / span ** power
        top, bottom = float(collected.max()), float(collected.min())
        if top - bottom <= zero:
            bottom = top
        for idx, bp in enumerate(self):
            if color_map == self.COLOR_MAP_CLASSIFICATION:
                ts = [f3(v, zero) for v in bp.curvature.ravel()]
            elif color_map == self.COLOR_MAP_CUT:
                ts = [f1(v) for v in bp.curvature.ravel()]
            else:
                ts = [f2(v, bottom, top) for v in bp.curvature.ravel()]
            bp.set_colors(*[tuple(h(t)) for t in ts])
'''

EVA = '''
import math

import numpy as np

from lab.colormaps import f1, f2, f3, h


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        # Krümmung an den vier Ecken: das Netz so spiegeln, dass die Ecke vorne liegt
        werte = []
        for flaeche in self:
            grad_u, grad_v = flaeche.degree
            netz = np.asarray(flaeche.control_points, dtype=float)
            ecken = []
            for su in (1, -1):
                for sv in (1, -1):
                    Q = netz[::su, ::sv]
                    xu = su * grad_u * (Q[1, 0] - Q[0, 0])
                    xv = sv * grad_v * (Q[0, 1] - Q[0, 0])
                    xuu = grad_u * (grad_u - 1) * (Q[2, 0] - 2 * Q[1, 0] + Q[0, 0])
                    xvv = grad_v * (grad_v - 1) * (Q[0, 2] - 2 * Q[0, 1] + Q[0, 0])
                    xuv = su * sv * grad_u * grad_v * (Q[1, 1] - Q[1, 0] - Q[0, 1] + Q[0, 0])
                    senkrecht = np.cross(xu, xv)
                    senkrecht /= np.linalg.norm(senkrecht)
                    erste = np.array([[xu @ xu, xu @ xv], [xu @ xv, xv @ xv]])
                    zweite = np.array([[senkrecht @ xuu, senkrecht @ xuv], [senkrecht @ xuv, senkrecht @ xvv]])
                    weingarten = np.linalg.solve(erste, zweite)
                    k_gauss = float(np.linalg.det(weingarten))
                    k_mittel = float(np.trace(weingarten)) / 2
                    wurzel = math.sqrt(max(k_mittel * k_mittel - k_gauss, 0.0))
                    if curvature_mode == self.CURVATURE_GAUSSIAN:
                        ecken.append(k_gauss)
                    elif curvature_mode == self.CURVATURE_AVERAGE:
                        ecken.append(k_mittel)
                    elif curvature_mode == self.CURVATURE_PRINCIPAL_MAX:
                        ecken.append(k_mittel + wurzel)
                    else:
                        ecken.append(k_mittel - wurzel)
            flaeche.set_curvature(*ecken)
            werte.extend(ecken)
        # Farben
        alle = self.control_points.reshape(-1, 3)
        laenge = math.dist(alle.min(axis=0), alle.max(axis=0))
        schwelle = 1e-9 / laenge ** (2 if curvature_mode == self.CURVATURE_GAUSSIAN else 1)
        unten, oben = min(werte), max(werte)
        if oben - unten <= schwelle:
            unten = oben
        for flaeche in self:
            farben = []
            for k in flaeche.curvature.ravel():
                if color_map == self.COLOR_MAP_CUT:
                    farben.append(tuple(h(f1(k))))
                elif color_map == self.COLOR_MAP_LINEAR:
                    farben.append(tuple(h(f2(k, unten, oben))))
                else:
                    farben.append(tuple(h(f3(k, schwelle))))
            flaeche.set_colors(*farben)
'''


def _rename(source, names):
    """``source`` with every whole word of ``names`` replaced at once (a copy with renamed variables)."""
    return re.sub(r"\b(" + "|".join(sorted(names, key=len, reverse=True)) + r")\b", lambda m: names[m[0]], source)


def _reindent(source):
    """Two spaces of indentation instead of four, no spaces around operators and after commas, a blank line after
    every line, and the call of set_curvature over six lines with a trailing comma (a reformatted copy)."""
    lines = []
    for line in source.splitlines():
        code = line.lstrip(" ")
        indent = " " * ((len(line) - len(code)) // 2)
        code = re.sub(r" ([-+*/=<>]=?|@|\*\*) ", r"\1", code).replace(", ", ",")
        if code.startswith("pt.set_curvature("):
            lines.append(indent + "pt.set_curvature(")
            lines.extend(f"{indent}  {arg}," for arg in code[len("pt.set_curvature("):-1].split(","))
            code = ")"
        lines.extend([indent + code, ""] if code else [""])
    return "\n".join(lines)


def _recomment(source):
    """Other comments and a docstring (a re-commented copy)."""
    out = []
    for line in source.splitlines():
        if line.strip().startswith("#"):
            continue
        out.append(line)
        stripped = line.strip()
        indent = line[:len(line) - len(line.lstrip())]
        if stripped.startswith("def visualize_curvature"):
            out.append(indent + '    """Corner curvature of every patch, then a colour for each corner."""')
            out.append(indent + "    # <script>alert('hal')</script> my own comment")
        elif stripped.startswith("Tu ="):
            out[-1] += "  # first derivative along u"
        elif stripped.startswith("den ="):
            out.insert(len(out) - 1, indent + "# determinant of the first fundamental form")
        elif stripped.startswith("span ="):
            out.insert(len(out) - 1, indent + "# now the colours")
    return "\n".join(out) + "\n"


def _blocks(source):
    return source.strip().split("\n\n\n")


ADA = students.source()
FAY = _rename(ADA, {"values": "all_k", "patch": "piece", "P": "cpts", "at": "node", "bu": "net_u", "bv": "net_v",
                    "buu": "net_uu", "buv": "net_uv", "bvv": "net_vv", "corners": "kappas", "du": "xu", "dv": "xv",
                    "duu": "xuu", "duv": "xuv", "dvv": "xvv", "Q": "cr", "N": "unit", "root": "disc", "points": "pts",
                    "size": "diam", "tol": "eps", "kmin": "lo", "kmax": "hi", "colours": "rgb", "x": "kv", "t": "s",
                    "net": "grid", "m": "deg_u", "n": "deg_v", "E": "g11", "F": "g12", "G": "g22", "e": "h11",
                    "f": "h12", "g": "h22"})
GIL = "\n\n\n".join([_blocks(CEM)[0], _blocks(CEM)[5], _blocks(CEM)[4], _blocks(CEM)[3], _blocks(CEM)[1],
                     _blocks(CEM)[2]]) + "\n"
HAL = _recomment(DORA)
IVY = _reindent(BEN)
_EVA_CURVATURE = EVA[EVA.index("        werte = []"):EVA.index("        # Farben")]
JAN = (EVA[:EVA.index("        # Krümmung")] + "        # curvature at the corners: mirror the net so that the corner "
       "comes first\n" + _EVA_CURVATURE + '''        # colours, my way
        every = self.control_points.reshape(-1, 3)
        box = every.max(axis=0) - every.min(axis=0)
        cutoff = 1e-9 * (box @ box) ** (-1.0 if curvature_mode == self.CURVATURE_GAUSSIAN else -0.5)
        kmin_all = min(werte)
        kmax_all = max(werte)
        if abs(kmax_all - kmin_all) <= cutoff:
            kmin_all = kmax_all
        chooser = {
            self.COLOR_MAP_LINEAR: lambda z: h(f2(z, kmin_all, kmax_all)),
            self.COLOR_MAP_CUT: lambda z: h(f1(z)),
            self.COLOR_MAP_CLASSIFICATION: lambda z: h(f3(z, cutoff)),
        }[color_map]
        for patch in self:
            patch.set_colors(*map(tuple, map(chooser, patch.curvature.ravel())))
''')

#: Notebook 05: student -> (language of the notebook, the task cell).
SUBMISSIONS_05 = {"ada": ("en", ADA), "ben": ("en", BEN), "cem": ("en", CEM), "dora": ("en", DORA),
                  "eva": ("de", EVA), "fay": ("en", FAY), "gil": ("en", GIL), "hal": ("en", HAL), "ivy": ("en", IVY),
                  "jan": ("en", JAN)}
PLANTED = {("ada", "fay"): "renamed", ("cem", "gil"): "reordered", ("dora", "hal"): "re-commented",
           ("ben", "ivy"): "reformatted", ("eva", "jan"): "partial copy"}
HONEST = sorted(set(SUBMISSIONS_05))

F1_SOLUTION = "return min(max(x, 0.0), 1.0)"
F1_CLIP = "return float(np.clip(x, 0.0, 1.0))"
OLA_CODE = {"e414bd8b": '''def h(x):
    """The practical's colour ramp: 0 -> blue, 0.5 -> green, 1 -> red."""
    knots = [0.0, 0.25, 0.5, 0.75, 1.0]
    reds = [0.0, 0.0, 0.0, 1.0, 1.0]
    greens = [0.0, 1.0, 1.0, 1.0, 0.0]
    blues = [1.0, 1.0, 0.0, 0.0, 0.0]
    x = min(max(float(x), 0.0), 1.0)
    return tuple(float(np.interp(x, knots, channel)) for channel in (reds, greens, blues))
''', "5e3ced60": '''def f1(x):
    """Cut to [0, 1]."""
    return 0.0 if x < 0 else 1.0 if x > 1 else float(x)


def f2(x, kmin, kmax):
    """Linear from kmin (0) to kmax (1); 0.5 when kmin == kmax."""
    width = kmax - kmin
    return 0.5 if width == 0 else (x - kmin) / width


def f3(x, tol=1e-9):
    """Classification: 0 (negative), 0.5 (zero within tol), 1 (positive)."""
    return 0.5 if -tol <= x <= tol else (1.0 if x > 0 else 0.0)
'''}
PIA_CODE = {cell: _rename(src, {"width": "span", "knots": "stops", "channel": "ch"}).replace(
    '"""Cut to [0, 1]."""', '"""Clamp."""  # copied? no, my own') for cell, src in OLA_CODE.items()}
ANSWERS = {
    "kim": "f1 just clips the value to [0, 1]. Good: a value means the same colour on any model, no parameters "
           "needed. Bad: curvature outside [0, 1] is all blue or all red, so most of a real model is one colour.\n\n"
           "f2 stretches the range kmin to kmax over the whole ramp, so every model uses all colours. One outlier, "
           "e.g. the tip of the bump, makes everything else look the same, and zero is not a fixed colour.\n\n"
           "f3 only tells the sign: elliptic, parabolic or hyperbolic. Easy to read, no magnitude.",
    "lea": "f1 schneidet ab: gleiche Werte haben immer gleiche Farben, aber große Krümmungen sind alle rot und "
           "negative alle blau.\n\nf2 verteilt die Werte linear zwischen Minimum und Maximum; ein Ausreißer macht "
           "den Rest einfarbig, und die Null hat keine feste Farbe.\n\nf3 zeigt nur das Vorzeichen der Krümmung, "
           "also die Art der Punkte, nicht ihre Größe.",
    "max": "The cut map is simple and comparable between surfaces but saturates: anything above 1 is red and below "
           "0 blue. The linear map adapts to the data, which is nice for a single model, but the colours mean "
           "different things on each surface and an extreme value compresses the rest. The classification map is "
           "great for finding where K changes sign, but it throws the size of the curvature away.",
    "nia": "Advantages of f1: absolute colours. Disadvantages: clipping, since the interesting range depends on the "
           "units of the model.\nf2: uses the whole scale; but sensitive to outliers (a single peak), zero moves.\n"
           "f3: shows convex, saddle and flat regions; disadvantage: no information on how strong the curvature is, "
           "and the boundaries are thin lines that the corner sampling can miss.",
    "ola": "With f1 the colour is an absolute measure of curvature, which lets us compare two parts directly; the "
           "price is that everything outside the unit interval is saturated and the picture depends on the scale of "
           "the model.\n\nWith f2 every picture spans blue to red no matter what the surface is, so details are "
           "visible; the price is that the colour of zero wanders and a single sharp spot flattens the contrast "
           "everywhere else.\n\nWith f3 we see at a glance which regions are elliptic, hyperbolic or parabolic; the "
           "price is that the magnitude is lost completely.",
    "@pia": "With f1 the colour is an absolute measure of the curvature, which lets you compare two parts "
            "directly; the downside is that everything outside the unit interval is saturated and the picture "
            "depends on the scale of the model.\n\nWith f2 every picture spans from blue to red no matter what the "
            "surface is, so details are visible; the downside is that the colour of zero wanders and a single sharp "
            "spot flattens the contrast everywhere else.\n\nWith f3 you see at a glance which regions are elliptic, "
            "hyperbolic or parabolic; the downside is that the magnitude is lost completely.",
    "rob": "f1 (cut): + absolute, the same K always looks the same; - only [0,1] is resolved, negative K is uniformly "
           "blue.\nf2 (linear): + full colour range on every model; - outliers dominate, the zero level has no fixed "
           "colour, so sign is not visible.\nf3 (classification): + the type of each point is obvious; - magnitude "
           "is invisible, parabolic curves are thin and may fall between the corners. <img src=x onerror=alert(1)>",
    "sue": "**f1 (cut)**\n* + absolute: the same K always looks the same\n* - only [0,1] is resolved; negative K is "
           "uniformly blue\n\n**f2 (linear)**\n* + full colour range on every model\n* - outliers dominate, and the "
           "zero level has no fixed colour, so the sign is not visible\n\n**f3 (classification)**\n* + the type of "
           "each point is obvious\n* - magnitude is invisible; parabolic curves are thin and may fall between the "
           "corners",
}
#: Notebook 04: student -> (language, f1's line or None for the whole code of OLA_CODE / PIA_CODE).
SUBMISSIONS_04 = {"kim": ("en", F1_SOLUTION), "lea": ("de", F1_SOLUTION), "max": ("en", F1_CLIP),
                  "nia": ("en", F1_CLIP), "rob": ("en", F1_CLIP), "sue": ("en", F1_CLIP), "ola": ("en", OLA_CODE),
                  "@pia": ("en", PIA_CODE)}


def _exercise(assignment, lang):
    return nbformat.read(ROOT / "exercises" / lang / f"{assignment}.ipynb", as_version=4)


def _write(subs, student, assignment, nb):
    path = subs / student / f"{assignment}.ipynb"
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, path)
    return path


def _folder_05(subs):
    for student, (lang, code) in SUBMISSIONS_05.items():
        nb = _exercise(ID05, lang)
        next(c for c in nb.cells if "class MyBezierPatches" in c.source).source = textwrap.dedent(code).strip() + "\n"
        _write(subs, student, ID05, nb)
    solution = nbformat.read(ROOT / "solutions" / "en" / f"{ID05}.ipynb", as_version=4)  # zoe's copy of the answer
    nb = _exercise(ID05, "en")
    task = next(c for c in nb.cells if "class MyBezierPatches" in c.source)
    task.source = next(c.source for c in solution.cells if "class MyBezierPatches" in c.source)
    _write(subs, "zoe", ID05, nb)
    (subs / "bad").mkdir()
    (subs / "bad" / f"{ID05}.ipynb").write_text('{"cells": [')  # invalid JSON
    (subs / "list").mkdir()
    (subs / "list" / f"{ID05}.ipynb").write_text("[1, 2, 3]")
    (subs / "link").mkdir()
    (subs / "link" / f"{ID05}.ipynb").symlink_to(subs / "ada" / f"{ID05}.ipynb")
    nb = _exercise(ID05, "en")
    next(c for c in nb.cells if "class MyBezierPatches" in c.source).source = "x = 1\n" * 50_000
    _write(subs, "huge", ID05, nb)


def _folder_04(subs):
    question = "bfbc93a2"
    for student, (lang, code) in SUBMISSIONS_04.items():
        nb = _exercise(ID04, lang)
        cells = {c.get("id"): c for c in nb.cells}
        if isinstance(code, dict):
            for cell, source in code.items():
                cells[cell].source = source
        else:
            source = cells["5e3ced60"].source
            stub = next(line for line in source.splitlines() if "raise NotImplementedError" in line)
            cells["5e3ced60"].source = source.replace(stub, "    " + code, 1)
        cells[question].source = ANSWERS[student]
        _write(subs, student, ID04, nb)


def _pairs(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    """Both folders, compared once: notebook 05 through :func:`similarity.compare` (the result is read by the tests),
    notebook 04 through the command line, in English and in German."""
    root = tmp_path_factory.mktemp("similarity")
    subs05, subs04 = root / "subs05", root / "subs04"
    _folder_05(subs05)
    _folder_04(subs04)
    result = similarity.compare(subs05)
    similarity.write_page(result, root / "05.html", "en")
    similarity.write_csv(result, root / "05.csv")
    assert similarity.main([str(subs04), "-o", str(root / "04.html"), "--csv", str(root / "04.csv")]) == 0
    with pytest.MonkeyPatch.context() as mp, i18n.using("de"):  # LAB_LANG alone yields to an earlier set_language
        mp.setenv("LAB_LANG", "de")
        assert similarity.main([str(subs04), "-o", str(root / "04-de.html")]) == 0
    return {"root": root, "subs05": subs05, "subs04": subs04, "result": result}


def _scores(result):
    return {tuple(sorted((p.a, p.b))): p.score for p in result.pairs}


def test_every_planted_copy_ranks_above_every_honest_pair(course):
    result = course["result"]
    scores = _scores(result)
    planted = {pair: scores.get(pair, 0.0) for pair in PLANTED}
    honest = {(a, b): scores.get((a, b), 0.0) for i, a in enumerate(HONEST) for b in HONEST[i + 1:]
              if (a, b) not in PLANTED}
    assert len(planted) == 5 and len(honest) == 40
    lowest_copy, highest_honest = min(planted.values()), max(honest.values())
    assert lowest_copy > highest_honest + 0.3, (planted, sorted(honest.items(), key=lambda kv: -kv[1])[:5])
    assert {tuple(sorted((p.a, p.b))) for p in result.pairs[:5]} == set(PLANTED)
    for pair, how in PLANTED.items():
        assert planted[pair] >= (0.6 if how == "partial copy" else 0.9), (how, planted[pair])
    assert scores[("eva", "jan")] < 0.95  # the partial copy: only the curvature half
    assert all(p.part == "code" for p in result.pairs)  # notebook 05 has no written question


def test_the_scores_are_the_same_in_every_run(course):
    """copydetect hashes with Python's per-process salted hash; with the window 1 every k-gram is a fingerprint, so the
    salt changes nothing: another process with its own salt ranks with the same scores (with a window of 11 they
    differ by about 1 %)."""
    code = ("import json, sys; from lab.teaching.course import similarity as s; r = s.compare(sys.argv[1]); "
            "print(json.dumps([[p.a, p.b, p.score] for p in r.pairs]))")
    out = subprocess.run([sys.executable, "-c", code, str(course["subs05"])], capture_output=True, text=True,
                         check=True, env={**os.environ, "PYTHONHASHSEED": "12345"}, cwd=ROOT).stdout
    assert json.loads(out) == [[p.a, p.b, p.score] for p in course["result"].pairs]


def test_what_is_compared_is_what_the_student_wrote(course):
    subs = {s.student: s for s in course["result"].submissions}
    assert set(subs) == set(SUBMISSIONS_05) | {"zoe", "huge"}
    task = 1 + next(k for k, c in enumerate(_exercise(ID05, "en").cells) if "class MyBezierPatches" in c.source)
    for student in SUBMISSIONS_05:
        code = subs[student].texts["code"]
        assert code.startswith(f"# ── {task} ──\n"), code[:80]  # the task cell alone: the hand-out's others are left out
        assert code.count("# ── ") == 1
        assert "CurvatureExplorer" not in code and "NotImplementedError" not in code
    assert "Krümmung an den vier Ecken" in subs["eva"].texts["code"]  # her German notebook: its hand-out left out too
    assert subs["zoe"].reference_share > 0.95  # the reference solution, handed in: shown per student
    assert max(subs[s].reference_share for s in SUBMISSIONS_05) < 0.7
    assert not any("zoe" in (p.a, p.b) for p in course["result"].pairs)  # counts for nobody between students


def test_bad_notebooks_are_noted_and_skipped(course, capsys):
    result = course["result"]
    skipped = dict(result.skipped)
    assert set(skipped) == {f"bad/{ID05}.ipynb", f"list/{ID05}.ipynb", f"link/{ID05}.ipynb"}
    assert "not a notebook" in skipped[f"bad/{ID05}.ipynb"] and "JSON list" in skipped[f"list/{ID05}.ipynb"]
    assert "symbolic link" in skipped[f"link/{ID05}.ipynb"]
    huge = next(s for s in result.submissions if s.student == "huge")
    assert len(huge.texts["code"]) == similarity.MAX_CODE and "cut to the first 50000 characters" in huge.notes[0]
    page = (course["root"] / "05.html").read_text()
    assert "Not compared" in page and f"bad/{ID05}.ipynb" in page
    assert similarity.main([str(course["subs05"]), "-o", str(course["root"] / "again.html")]) == 0
    assert f"list/{ID05}.ipynb not compared: not a notebook" in capsys.readouterr().err


def test_short_necessarily_alike_code_is_not_flagged(course, monkeypatch):
    """f1 is one line: written like the reference solution (kim, lea) or with np.clip (max, nia, rob, sue), it is
    alike in all of them and no pair is flagged for it; without the shortest stretch that counts it would be."""
    _header, rows = _pairs(course["root"] / "04.csv")
    listed = {tuple(sorted(r[:2])): r for r in rows}
    one_liners = ["kim", "lea", "max", "nia", "rob", "sue"]
    for i, a in enumerate(one_liners):
        for b in one_liners[i + 1:]:
            assert (a, b) not in listed or listed[a, b][3] == "written", listed[a, b]  # never their code
    assert ("kim", "lea") not in listed and ("max", "nia") not in listed
    monkeypatch.setitem(similarity.MIN_REGION, "code", similarity.NOISE)
    loose = {tuple(sorted((p.a, p.b))): p for p in similarity.compare(course["subs04"]).pairs}
    assert "code" in loose[("max", "nia")].matches  # the protection is the shortest stretch


def test_written_copies_are_found_apart_from_the_code(course):
    _header, rows = _pairs(course["root"] / "04.csv")
    listed = {tuple(sorted(r[:2])): r for r in rows}
    both, answer = listed[("'@pia", "ola")], listed[("rob", "sue")]
    assert both[3] == "both" and answer[3] == "written"
    assert float(both[2]) > 0.8 and float(answer[2]) > 0.5
    others = [float(r[2]) for key, r in listed.items() if key not in (("'@pia", "ola"), ("rob", "sue"))]
    assert max(others, default=0.0) < float(answer[2]) - 0.3


def test_the_csv_lists_the_ranked_pairs(course):
    header, rows = _pairs(course["root"] / "05.csv")
    assert header == ["student_a", "student_b", "score", "part"]
    scores = [float(r[2]) for r in rows]
    assert scores == sorted(scores, reverse=True) and len(rows) == len(course["result"].pairs) >= 5
    assert {r[3] for r in rows} == {"code"}
    assert [tuple(sorted(r[:2])) for r in rows[:5]] == [tuple(sorted((p.a, p.b))) for p in course["result"].pairs[:5]]
    _header, rows04 = _pairs(course["root"] / "04.csv")
    assert ("'@pia", "ola") in {tuple(sorted(r[:2])) for r in rows04}  # @pia quoted: no formula in a spreadsheet


def test_the_page_escapes_student_text_and_needs_nothing_from_the_network(course):
    for name in ("05.html", "04.html", "04-de.html"):
        page = (course["root"] / name).read_text()
        assert "<script" not in page.lower() and "<img" not in page.lower() and "<link" not in page.lower()
        assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", page, re.IGNORECASE)
        assert "@import" not in page and "url(" not in page
    page05 = (course["root"] / "05.html").read_text()
    assert "# &lt;script&gt;alert(&#x27;hal&#x27;)&lt;/script&gt; my own comment" in page05  # hal's comment, as text
    assert "&lt;img src=x onerror=alert(1)&gt;" in (course["root"] / "04.html").read_text()
    assert page05.count("<mark>") >= 10 and "<section id='pair-1'>" in page05


def test_the_page_says_it_is_evidence_not_a_verdict_in_both_languages(course):
    """The German page needs the merged catalogue (lab.po with this module's messages, compiled)."""
    english = (course["root"] / "04.html").read_text()
    german = (course["root"] / "04-de.html").read_text()
    assert "Evidence, not a verdict." in english and "<html lang='en'>" in english
    assert "Ein Indiz, kein Urteil." in german and "<html lang='de'>" in german
    assert "Evidence, not a verdict." not in german


def test_a_folder_as_collect_writes_it(course, tmp_path):
    """Homes collected by ``curvature-lab collect``: the assignment comes from collected.csv (a stray notebook in a
    student's folder does not make it two), and the copy is found."""
    from lab.teaching.course import collect

    for student in ("ada", "ben", "fay"):
        home = tmp_path / "home" / student / "curvature-lab" / "exercises" / "en"
        home.mkdir(parents=True)
        (home / f"{ID05}.ipynb").write_bytes((course["subs05"] / student / f"{ID05}.ipynb").read_bytes())
    subs = tmp_path / "subs"
    collect.collect(tmp_path / "home", ID05, "2030-01-01T00:00+00:00", subs)
    (subs / "ben" / "scratch.ipynb").write_bytes((subs / "ben" / f"{ID05}.ipynb").read_bytes())
    assert similarity.main([str(subs), "-o", str(tmp_path / "page.html"), "--csv", str(tmp_path / "pairs.csv")]) == 0
    _header, rows = _pairs(tmp_path / "pairs.csv")
    assert [sorted(r[:2]) for r in rows] == [["ada", "fay"]]
    assert ID05 in (tmp_path / "page.html").read_text()


def _copy(course, root, names, assignment=ID05):
    """Students' notebooks of the module's set-up into ``root/subs``."""
    source = course["subs05" if assignment == ID05 else "subs04"]
    for name in names:
        (root / "subs" / name).mkdir(parents=True, exist_ok=True)
        data = (source / name / f"{assignment}.ipynb").read_bytes()
        (root / "subs" / name / f"{assignment}.ipynb").write_bytes(data)


#: Bad input: how to make it in ``root`` (``subs`` the folder given), further options, the message.
BAD_INPUT = {
    "missing folder": (lambda course, root: None, [], "subs does not exist; expected a folder of submissions"),
    "a file": (lambda course, root: (root / "subs").write_text("x"), [],
               "subs is a file; expected a folder of submissions"),
    "no notebooks": (lambda course, root: (root / "subs").mkdir(), [],
                     "holds no notebooks; expected SUBS/<student>/<ID>.ipynb"),
    "unknown assignment": (lambda course, root: _copy(course, root, ["ada", "ben"]), ["--assignment", "99_nothing"],
                           "unknown assignment '99_nothing': no exercise 99_nothing.ipynb in"),
    "one readable notebook": (lambda course, root: _copy(course, root, ["ada", "bad"]), [],
                              "1 readable notebook(s) of 05_visualize_curvature; at least 2 are needed"),
    "two assignments": (lambda course, root: (_copy(course, root, ["ada", "ben"]), _copy(course, root, ["kim"], ID04)),
                        [], "holds notebooks of several assignments (04_color_maps, 05_visualize_curvature)"),
    "no folder for the page": (lambda course, root: _copy(course, root, ["ada", "ben"]), ["-o", "{root}/no/page.html"],
                               "/no does not exist"),
}


@pytest.mark.parametrize("case", sorted(BAD_INPUT))
def test_bad_input_is_an_error_that_says_what_was_expected(course, tmp_path, capsys, case):
    make, options, message = BAD_INPUT[case]
    make(course, tmp_path)
    argv = [str(tmp_path / "subs"), "-o", str(tmp_path / "page.html")] + [o.format(root=tmp_path) for o in options]
    try:
        code = similarity.main(argv)
    except SystemExit as exc:  # argparse's error
        code = exc.code
    assert code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "page.html").exists()


def test_the_verb_is_registered(course, tmp_path):
    from lab import cli

    assert list(cli.VERBS).index("similarity") == list(cli.VERBS).index("collect") + 1
    assert cli.main(["similarity", str(course["subs04"]), "-o", str(tmp_path / "page.html")]) == 0
    assert "Evidence, not a verdict." in (tmp_path / "page.html").read_text()
