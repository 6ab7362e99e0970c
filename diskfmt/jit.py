"""Optional compilation of hot loops with numba.

The kernels are plain Python written in numba's subset; with numba installed
they are compiled on first use, without it they run as they are (same results,
slower).  ``RIG_NO_JIT=1`` turns compilation off, e.g. to compare."""

import os

try:
    if os.environ.get("RIG_NO_JIT"):
        raise ImportError
    from numba import njit as _njit

    def jit(fn):
        return _njit(cache=True, nogil=True)(fn)

    ENABLED = True
except ImportError:                       # pragma: no cover - exercised without numba
    def jit(fn):
        return fn

    ENABLED = False
