"""Students' visualize_curvature with the mistakes real students make, as source code (for the notebook and the
grader) and as a class (for lab.check).  ``source()`` with no argument is a correct solution written the way a
student writes it: loops over the control net, the corners with index -1, the practical's formulas."""

import textwrap

TEMPLATE = '''
import math

import numpy as np

from lab.colormaps import f1, f2, f3, h


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        # calculate curvatures at each corner point
        values = []
        for patch in self:
            P = patch.control_points
            {degrees}

            def at(i, j):
                return P[{index}]

            bu = [[{bu} * (at(i + 1, j) - at(i, j)) for j in range(n + 1)] for i in range(m)]
            bv = [[{bv} * (at(i, j + 1) - at(i, j)) for j in range(n)] for i in range(m + 1)]
            buu = [[{buu} * (at(i + 2, j) - 2 * at(i + 1, j) + at(i, j)) for j in range(n + 1)] for i in range(m - 1)]
            buv = [[{buv} * (at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j)) for j in range(n)]
                   for i in range(m)]
            bvv = [[{bvv} * (at(i, j + 2) - 2 * at(i, j + 1) + at(i, j)) for j in range(n - 1)] for i in range(m + 1)]
            corners = []
            for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
                du, dv, duu, duv, dvv = (np.asarray(net[-a][-b]) for net in (bu, bv, buu, buv, bvv))
                Q = np.cross(du, dv)
                N = Q / {norm}
                E, F, G = du @ du, du @ dv, dv @ dv
                e, f, g = N @ duu, N @ duv, N @ dvv
                K = (e * g - f * f) / (E * G - F * F)
                H = (e * G - 2 * f * F + g * E) / (2 * (E * G - F * F))
                root = {root}
                corners.append({{self.CURVATURE_GAUSSIAN: K, self.CURVATURE_AVERAGE: H,
                                self.CURVATURE_PRINCIPAL_MAX: H + root,
                                self.CURVATURE_PRINCIPAL_MIN: H - root}}[curvature_mode])
            patch.set_curvature(*{corners})
            values.extend(corners)
        # set colors according to color map
        points = self.control_points.reshape(-1, 3)
        size = np.linalg.norm(points.max(axis=0) - points.min(axis=0))
        tol = {tol}
        kmin, kmax = min(values), max(values)
        if kmax - kmin <= tol:
            kmin = kmax
        for patch in self:
            colours = []
            for x in patch.curvature.ravel():
                if color_map == self.COLOR_MAP_LINEAR:
                    t = {linear}
                elif color_map == self.COLOR_MAP_CUT:
                    t = f1(x)
                else:
                    t = {classification}
                colours.append(tuple(h(t)))
            patch.set_colors(*colours)
'''

RIGHT = {"degrees": "m, n = patch.degree", "index": "i][j", "bu": "m", "bv": "n", "buu": "m * (m - 1)",
         "buv": "m * n", "bvv": "n * (n - 1)", "norm": "np.linalg.norm(Q)", "root": "math.sqrt(max(H * H - K, 0.0))",
         "corners": "corners",
         "tol": "1e-9 / size ** (2 if curvature_mode == self.CURVATURE_GAUSSIAN else 1)",
         "linear": "f2(x, kmin, kmax)", "classification": "f3(x, tol)"}

#: Mistakes by name: the template's fields they change.
MISTAKES = {
    "bu_bv_without_m_n": {"bu": "1", "bv": "1"},
    "buv_(m-1)n": {"buv": "(m - 1) * n"},
    "buv_without_mn": {"buv": "1"},
    "buu_m_bvv_n": {"buu": "m", "bvv": "n"},
    "bu_1_buu_m": {"bu": "1", "buu": "m"},
    "bv_m_bvv_1": {"bv": "m", "bvv": "1"},
    "second_derivatives_without_factors": {"buu": "1", "buv": "1", "bvv": "1"},
    "no_factors": {"bu": "1", "bv": "1", "buu": "1", "buv": "1", "bvv": "1"},
    "normal_over_norm_squared": {"norm": "(Q @ Q)"},
    "unnormalised_normal": {"norm": "1"},
    "hard_coded_factors_3_3": {"bu": "3", "bv": "3", "buu": "6", "buv": "9", "bvv": "6"},
    "hard_coded_degree_4_4": {"degrees": "m, n = 4, 4"},
    "swapped_degrees_in_loops": {"degrees": "n, m = patch.degree"},
    "swapped_degree_factors": {"bu": "n", "bv": "m", "buu": "n * (n - 1)", "bvv": "m * (m - 1)"},
    "transposed_loops": {"index": "j][i"},
    "sqrt_at_umbilics": {"root": "math.sqrt(H * H - K)"},
    "f2_divides_by_zero": {"linear": "(x - kmin) / (kmax - kmin)"},
    "f3_equals_zero": {"classification": "0.5 if x == 0 else float(x > 0)"},
    "f3_absolute_tolerance": {"tol": "1e-4"},
    "corner_order": {"corners": "(corners[0], corners[2], corners[1], corners[3])"},
}


def source(mistake=None):
    """The source of a notebook cell defining MyBezierPatches, with the named mistake (or none)."""
    fields = {**RIGHT, **(MISTAKES[mistake] if mistake else {})}
    return textwrap.dedent(TEMPLATE.format(**fields)).strip() + "\n"


def student_class(mistake=None):
    """MyBezierPatches with the named mistake, defined as a notebook cell would define it."""
    import lab

    namespace = {"lab": lab}
    exec(compile(source(mistake), f"<student {mistake}>", "exec"), namespace)  # noqa: S102 - our own test code
    return namespace["MyBezierPatches"]
