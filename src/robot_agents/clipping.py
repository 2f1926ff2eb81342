"""NumPy's one-pass clip, and when it gives exactly the bits of the two-pass one."""

from __future__ import annotations

import importlib

import numpy as np
import numpy.typing as npt

#: NumPy's one-pass clip ufunc, ``minimum(maximum(x, low), high)`` in one call (in
#: ``numpy._core.umath`` since NumPy 2, ``numpy.core.umath`` before; not in the stubs).
clip_ufunc: np.ufunc = importlib.import_module("numpy._core.umath" if hasattr(np, "_core") else "numpy.core.umath").clip


def one_pass_clip_exact(low: npt.NDArray[np.float64], high: npt.NDArray[np.float64]) -> bool:
    """True when ``clip_ufunc`` with these bounds returns exactly the bits of
    ``np.minimum(np.maximum(x, low), high)`` for every ``x``: they can only differ where
    ``x`` equals a bound of the other sign of zero (``-0.0`` against ``0.0``; which zero
    each returns is not specified across NumPy versions and SIMD paths), so no bound may
    be zero (NaN bounds never occur: they are rejected earlier)."""
    return not (np.any(low == 0.0) or np.any(high == 0.0))
