"""Surface interrogation: focal surfaces (``focal``), reflection lines and isophotes (``reflection``), both on
meshes (``meshes``), geodesics and polar isodistance curves (``geodesics/``), trimmed surfaces (``trimming/``).
May import numpy, scipy, triangle, and lab.geometry, lab.mesh and lab.model.
"""
