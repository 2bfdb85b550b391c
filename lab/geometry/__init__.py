"""Formulas on arrays: Bernstein/de Casteljau, B-spline/NURBS, derivatives, fundamental forms, K, H, κ1, κ2, the
colour maps that turn curvature into colours (practical section 4) and how they look with a colour-vision deficiency.
May import numpy, scipy, colorspacious (``vision``) and (``analytic`` only) sympy and mpmath; nothing of lab above.
"""
