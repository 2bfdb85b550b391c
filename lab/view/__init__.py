"""What a student sees: offscreen pictures (``render``, in the style of ``style``, with the legends of ``legend``;
the ``gallery`` of docs/) and the interactive explorers (``explorers/``).
May import pyvista, ipywidgets, trame, matplotlib and every layer below (geometry, mesh, model, interrogation).
Nothing here computes geometry: it shows what the layers below compute.
"""
