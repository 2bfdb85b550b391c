"""What a student sees: pictures (``render`` in the ``style`` with ``legend``s; ``gallery``) and the ``explorers/``.
May import pyvista, ipywidgets, trame, matplotlib and every layer below (geometry, mesh, model, interrogation).
Nothing here computes geometry: it shows what the layers below compute.
"""
