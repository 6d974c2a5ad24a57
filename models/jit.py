"""The decorator of the project's compiled numba kernels (`agent`, `skills`, `server`).

Each kernel module keeps its own LLVM intrinsics beside the kernels that call them:
numba's on-disk cache is checked against the cached function's own source file only.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

import numba


def njit(fn: Callable) -> Callable:
    """`numba.njit(cache=True)`, compiled in memory where no cache directory is writable."""
    try:
        return numba.njit(cache=True)(fn)
    except RuntimeError as exc:  # "cannot cache function ...: no locator available"
        warnings.warn(f"{fn.__module__}.{fn.__qualname__} compiles in memory, not cached: {exc}",
                      RuntimeWarning, stacklevel=2)
        return numba.njit(fn)
