"""Pictures against stored references, one tolerance for every picture test (test_mesh, test_pictures,
test_widgets, test_model_tools)."""

import os

import numpy as np


def assert_like_reference(image, reference, where=None):
    """``image`` (h, w, 3 or 4) equals the stored picture ``reference`` within the tolerance of a GL driver.

    A different driver may shift anti-aliased edges by a pixel: the mean difference stays below 3 (of 255) and
    fewer than 2 % of the pixels differ by more than 40.  ``LAB_UPDATE_REFERENCES=1`` rewrites the reference;
    ``where`` (a folder) keeps the picture for a look when the test fails.
    """
    import imageio.v3 as iio

    image = np.asarray(image)[..., :3]
    if os.environ.get("LAB_UPDATE_REFERENCES"):
        iio.imwrite(reference, image)
    if where is not None:
        iio.imwrite(os.path.join(where, "picture.png"), image)
    diff = np.abs(image.astype(float) - iio.imread(reference)[..., :3].astype(float))
    mean, frac = diff.mean(), np.mean(np.any(diff > 40, axis=-1))
    assert mean < 3.0 and frac < 0.02, (f"picture differs from {reference}: mean {mean:.2f}, {frac:.1%} pixels"
                                        + (f"; see {where}" if where is not None else ""))
