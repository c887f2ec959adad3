"""The image render() returns: a numpy array that a notebook shows inline."""

import numpy as np

from . import _fixpoint


class Picture(np.ndarray):
    """An image of fixpoint.render(): a plain numpy array (height, width, 3), uint8, uint16 or
    float32, that Jupyter and IPython show as the PNG `fixpoint render -o` would write
    (``_repr_png_``). Slices and arithmetic stay Pictures; one that is not an image any more
    (another shape) shows as an array.
    """

    def __new__(cls, array):
        return np.asarray(array).view(cls)

    def _repr_png_(self):
        a = np.asarray(self)
        if a.ndim != 3 or a.shape[2] != 3 or a.size == 0:
            return None
        if a.dtype == np.uint8:
            return _fixpoint.encode_png(a.astype(np.float32) / 255, 8)
        if a.dtype == np.uint16:
            return _fixpoint.encode_png(a.astype(np.float32) / 65535, 16)
        if a.dtype.kind == "f":
            return _fixpoint.encode_png(a.astype(np.float32), 8)
        return None
