"""The objects a student handles: surface classes (Bézier, B-spline/NURBS, analytic), the named example
surfaces (``surfaces``: the practical's, torus, catenoid, hood …) and the practical's ``BezierPatches``.
May import numpy and lab.geometry; lab.mesh only to turn patches into meshes and geomview files.
"""
