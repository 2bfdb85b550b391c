"""The practical's last step: the geomview export is read back and shown in the notebook, and Debian's geomview
loads it (a snapshot under Xvfb; the developers' guide, docs/developers/runtime.md)."""

import shutil
import subprocess
import time

import numpy as np
import pytest

import lab
from lab import mesh as M
from lab import render, surfaces


@pytest.fixture(scope="module")
def coloured():
    p = surfaces.practical().to_bezier_patches().refine(1)
    p.visualize_curvature(p.CURVATURE_GAUSSIAN, p.COLOR_MAP_CLASSIFICATION)
    return p


def test_cbez_read_back_as_a_mesh_keeps_points_and_colours(coloured, tmp_path):
    path = tmp_path / "practical.bez"
    coloured.write_cbez(path)
    mesh = M.read_geomview(path, resolution=4)
    assert mesh.field_data["geomview_format"][0] == "CBEZ333"
    # the corners of the patches are points of the mesh, with their corner colours
    corners = coloured.evaluate(np.array([0.0, 1.0])[:, None], np.array([0.0, 1.0])[None, :]).reshape(-1, 3)
    d, idx = _nearest(np.asarray(mesh.points), corners)
    assert d.max() < 1e-9
    want = np.round(255 * coloured.colors.reshape(-1, 3)).astype(int)
    got = np.asarray(mesh.point_data["RGB"], dtype=int)[idx]
    # welded corners average the colours of the patches meeting there: compare where all agree
    assert np.mean(np.all(np.abs(got - want) <= 1, axis=1)) > 0.9
    # the inside of a patch is the Bézier surface, not the bilinear quad
    mid = coloured.evaluate(np.array(0.5), np.array(0.5)).reshape(-1, 3)
    assert _nearest(np.asarray(mesh.points), mid)[0].max() < 1e-9


def test_off_read_back_and_shown(coloured, tmp_path):
    path = tmp_path / "practical.off"
    coloured.write_off(path)
    mesh = M.read_geomview(path)
    assert mesh.field_data["geomview_format"][0] == "COFF"
    assert mesh.n_points == coloured.to_mesh().n_points
    image = render.picture(path, window_size=(320, 240))
    assert image.shape == (240, 320, 3)


def test_show_takes_the_exported_file(coloured, tmp_path):
    path = tmp_path / "practical.bez"
    coloured.write_cbez(path)
    image = render.picture(path, window_size=(400, 300))
    classes = {tuple(int(c) for c in x) for x in np.round(255 * lab.colormaps.h(np.array([0.0, 1.0])))}
    near = [np.any(np.all(np.abs(image.astype(int) - np.array(c)) < 60, axis=-1)) for c in classes]
    assert all(near), "the picture of the file shows the classification's blue and red"


def test_not_a_geomview_file_is_named(tmp_path):
    path = tmp_path / "x.bez"
    path.write_text("BEZ333\n0 0 0\n")
    with pytest.raises(ValueError, match=r"x.bez: not a geomview file the lab writes .*got 'BEZ333'"):
        M.read_geomview(path)


def _nearest(points, queries):
    from scipy.spatial import cKDTree

    return cKDTree(points).query(queries)


# -- Debian's geomview under Xvfb ---------------------------------------------------------------------------------

needs_geomview = pytest.mark.skipif(not (shutil.which("geomview") and shutil.which("Xvfb")),
                                    reason="Debian's geomview and xvfb are not installed (apt-get install geomview xvfb)")


@pytest.fixture
def display():
    """A private X display (Xvfb chooses a free number and writes it to a pipe)."""
    import os

    read, write = os.pipe()
    proc = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "800x600x24", "-nolisten", "tcp"],
                            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as fh:
        number = fh.readline().strip()
    try:
        yield f":{number}"
    finally:
        proc.terminate()
        proc.wait(timeout=30)


@needs_geomview
def test_debian_geomview_shows_the_coloured_export(coloured, tmp_path, display):
    bez = tmp_path / "practical.bez"
    coloured.write_cbez(bez)
    snap = tmp_path / "snap.ppm"
    script = tmp_path / "show.gcl"
    # commands given with -c run before the camera exists; a script file runs after (docs/developers/runtime.md)
    script.write_text(f'(load "{bez}") (sleep-for 2) (look) (sleep-for 1) '
                      f'(snapshot focus "{snap}" ppmscreen) (sleep-for 1) (exit)\n')
    env = {"DISPLAY": display, "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    done = subprocess.run(["geomview", "-nopanels", "-wins", "1", str(script)], env=env, cwd=tmp_path,
                          capture_output=True, text=True, timeout=240, check=False)
    for _ in range(20):  # the snapshot is written before geomview exits; allow the file system a moment
        if snap.exists():
            break
        time.sleep(0.5)
    assert snap.exists(), f"geomview wrote no snapshot: {done.returncode} {done.stderr[-500:]}"
    from PIL import Image

    image = np.asarray(Image.open(snap).convert("RGB")).astype(int)
    background = np.median(image.reshape(-1, 3), axis=0)
    drawn = np.any(np.abs(image - background) > 30, axis=-1)
    assert drawn.mean() > 0.05, f"the snapshot is blank: {drawn.mean():.1%} of it differs from the background"
    # the classification's colours: blue (hyperbolic, most of the surface) and red (elliptic, the bump)
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    blue = np.mean((b > r + 40) & (b > g + 40))
    red = np.mean((r > g + 40) & (r > b + 40))
    assert blue > 0.01 and red > 0.0005, f"blue {blue:.2%}, red {red:.2%} of the snapshot"
