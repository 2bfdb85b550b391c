"""The static fallback: notebooks converted with nbconvert keep their pictures, explorers included."""

import base64
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
EXPLORER_NOTEBOOKS = [p for p in sorted((ROOT / "solutions" / "en").glob("*.ipynb")) if "Explorer(" in p.read_text()]
# the German notebooks share the code; one of them is exported too (German titles and labels, set_language("de"))
EXPLORER_NOTEBOOKS.append(ROOT / "solutions" / "de" / "05_visualize_curvature.ipynb")


def _picture_cells(path):
    """Code cells that produce a picture: render.show, an explorer, or a matplotlib figure."""
    import nbformat

    nb = nbformat.read(path, as_version=4)
    return [c for c in nb.cells if c.cell_type == "code" and re.search(r"render\.show\(|Explorer\(|plt\.show\(\)", c.source)]


@pytest.mark.parametrize("path", EXPLORER_NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_nbconvert_html_contains_the_pictures(tmp_path, path):
    out = tmp_path / (path.stem + ".html")
    result = subprocess.run(
        [sys.executable, "-m", "jupyter", "nbconvert", "--to", "html", "--execute",
         "--ExecutePreprocessor.timeout=600", f"--output-dir={tmp_path}", str(path)],
        capture_output=True, text=True, timeout=900, cwd=tmp_path, check=False,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    html = out.read_text()
    images = re.findall(r'src="data:image/png;base64,([^"]+)"', html)
    expected = len(_picture_cells(path))
    assert len(images) >= expected, f"{len(images)} pictures in {out}, expected at least {expected}"
    # no widget views (they would need widget JavaScript from the network to show anything)
    assert '<script type="application/vnd.jupyter.widget-view+json">' not in html
    import io

    from PIL import Image

    for data in images:
        img = np.asarray(Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB")).astype(int)
        assert np.mean(np.any(np.abs(img - 255) > 20, axis=-1)) > 0.02, "a blank picture in the export"
