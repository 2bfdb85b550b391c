"""Surface interrogation: focal surfaces (``focal``), reflection lines and isophotes (``reflection``), both on meshes
(``meshes``), geodesics and polar isodistance curves (``geodesics/``), trimmed surfaces (``trimming/``), real parts (``cad/``).
May import numpy, scipy, triangle, lab.geometry, lab.mesh and lab.model; OCP and rhino3dm only inside cad/, when called.
"""
