"""The curvature-lab command line."""

import subprocess
import sys

import numpy as np
import pytest

from lab import cli
from lab import mesh as M


def run(*args):
    return subprocess.run([sys.executable, "-m", "lab.cli", *args], capture_output=True, text=True, timeout=300,
                          check=False)


def test_render_png_is_not_blank(tmp_path):
    import imageio.v3 as iio

    out = tmp_path / "practical.png"
    result = run("render", "--surface", "practical", "--curvature", "gaussian", "--color-map", "linear",
                 "--depth", "2", "--window-size", "400x300", "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert f"wrote {out}" in result.stderr
    assert "refining to depth 2: 784 patches" in result.stderr  # the progress display
    image = iio.imread(out)
    assert image.shape == (300, 400, 3)
    covered = np.any(image < 250, axis=-1)
    assert 0.05 < covered.mean() < 0.9
    assert len(np.unique(image[covered].reshape(-1, 3) // 32, axis=0)) > 3  # shaded and coloured, not one flat colour


def test_render_off_is_valid(tmp_path):
    out = tmp_path / "torus.off"
    assert cli.main(["render", "--surface", "torus", "--depth", "1", "--quiet", "-o", str(out)]) == 0
    points, faces, colors = M.read_off(out)
    # 4 x 4 knot spans, refined once: 8 x 8 quads on a closed torus (seams welded)
    assert len(faces) == 64 and len(points) == 64
    assert all(len(f) == 4 for f in faces)
    assert colors.shape == (64, 4) and colors.min() >= 0 and colors.max() <= 1


@pytest.mark.parametrize("suffix", [".vtk", ".html", ".bez"])
def test_other_outputs(tmp_path, suffix):
    import warnings

    out = tmp_path / f"saddle{suffix}"
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        assert cli.main(["render", "--surface", "saddle", "--depth", "1", "--quiet", "-o", str(out)]) == 0
    assert out.stat().st_size > 100
    assert not [w for w in seen if "deprecated" in str(w.message)]  # PyVista 0.49: trame-pyvista's export_html
    if suffix == ".bez":
        nets, _, _colors = M.read_cbez(out)
        assert nets.shape == (4, 3, 3, 3)
    if suffix == ".vtk":
        import pyvista as pv

        m = pv.read(out)
        assert {"K", "H", "k1", "k2", "RGB"} <= set(m.point_data)


def test_analytic_surface_renders_on_a_grid(tmp_path):
    out = tmp_path / "catenoid.vtk"
    assert cli.main(["render", "--surface", "catenoid", "--curvature", "mean", "--depth", "0", "--quiet", "-o", str(out)]) == 0
    import pyvista as pv

    m = pv.read(out)
    np.testing.assert_allclose(m.point_data["H"], 0, atol=1e-12)


def test_help_and_errors(tmp_path):
    result = run("render", "--help")
    assert result.returncode == 0 and "--color-map" in result.stdout and "--depth" in result.stdout
    result = run("render", "--surface", "teapot", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2 and "invalid choice: 'teapot'" in result.stderr and "practical" in result.stderr
    result = run("render", "--color-map", "jet", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2 and "invalid choice: 'jet'" in result.stderr
    result = run("render", "-o", str(tmp_path / "x.jpg"))
    assert result.returncode == 2 and "unknown output type '.jpg'" in result.stderr
    result = run("render", "--depth", "12", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2 and "--depth must be between 0 and 8; got 12" in result.stderr
    result = run("render", "--surface", "catenoid", "-o", str(tmp_path / "x.bez"))
    assert result.returncode == 2 and "analytic, not made of Bézier patches" in result.stderr
    result = run("render", "-o", str(tmp_path / "missing" / "x.png"))
    assert result.returncode == 2 and "does not exist" in result.stderr


def test_render_options_for_pictures(tmp_path):
    import imageio.v3 as iio

    def picture(*options, name="p.png"):
        out = tmp_path / name
        assert cli.main(["render", "--surface", "practical", "--depth", "2", "--window-size", "400x300", "--quiet",
                         *options, "-o", str(out)]) == 0
        return iio.imread(out)[..., :3].astype(int)

    default = picture(name="default.png")
    assert np.mean(np.abs(picture("--camera=-60,35", name="camera.png") - default)) > 3  # another view
    assert np.mean(np.abs(picture("--camera", "-60,35", name="camera2.png") - picture("--camera=-60,35"))) == 0
    ranged = picture("--vmin", "-1", "--vmax", "1", name="ranged.png")
    assert np.mean(np.abs(ranged - default)) > 3  # other colours for the same surface
    bare = picture("--no-legend", "--no-title", name="bare.png")

    def green(img):  # the middle of the practical's ramp h: on the colour bar, not on this (blue) surface
        return int(np.count_nonzero((img[..., 1] > 200) & (img[..., 0] < 80) & (img[..., 2] < 80)))

    assert green(default) > 100 and green(bare) < 20  # the colour bar, and none with --no-legend
    assert not np.array_equal(bare, default) and np.mean(np.any(bare[:25] < 100, axis=-1)) < np.mean(
        np.any(default[:25] < 100, axis=-1))  # no title text on top


def test_render_option_errors(tmp_path):
    out = str(tmp_path / "x.png")
    result = run("render", "--color-map", "cut", "--vmin", "0", "-o", out)
    assert result.returncode == 2 and "--vmin/--vmax apply to the colour maps linear, dill, symmetric" in result.stderr
    result = run("render", "--vmin", "2", "--vmax", "1", "-o", out)
    assert result.returncode == 2 and "--vmin must be smaller than --vmax; got 2 and 1" in result.stderr
    result = run("render", "--color-map", "dill", "--vmax", "1", "-o", out)
    assert result.returncode == 2 and "Dill's bands need both --vmin and --vmax" in result.stderr
    result = run("render", "--camera", "east", "-o", out)
    assert result.returncode == 2 and "camera must look like AZIMUTH,ELEVATION" in result.stderr
    result = run("render", "--camera", "0,120", "-o", out)
    assert result.returncode == 2 and "elevation must lie between -90 and 90" in result.stderr
