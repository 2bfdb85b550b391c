"""OpenCASCADE (cadquery-ocp-novtk) versions of lab surfaces, for the tests and benchmarks/curvature.py."""

from lab.interrogation.cad.write import occ_bspline as occt_surface  # the library's own conversion (lab.write uses it)

__all__ = ["occt_surface"]
