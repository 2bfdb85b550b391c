"""OpenCASCADE (cadquery-ocp-novtk) helpers for the tests and benchmarks/curvature.py."""

from lab.interrogation.cad.writer import occ_bspline as occt_surface  # the library's own conversion (lab.write uses it)

__all__ = ["occ_faces", "occt_surface"]


def occ_faces(path):
    """The file's faces as OpenCASCADE's TopoDS_Face objects, in the reader's order (the lab's face indices)."""
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp

    from lab.interrogation.cad import occ

    shape = occ.occ_shape(path)
    faces = occ._shape_map()
    TopExp.MapShapes_s(shape, TopAbs_FACE, faces)
    return [occ._cast("Face")(faces.FindKey(i + 1)) for i in range(faces.Extent())]
