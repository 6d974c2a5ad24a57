"""The numba decorator of the compiled kernels: cached, or in memory where caching is impossible."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path

import numba

KERNEL_MODULES = ("_lsap", "bottleneck", "_bigint", "_kernels")  # call each other
_warned = False


def _drop_stale_caches() -> None:
    """Deletes the in-tree numba caches of all kernel modules when any of their sources changed.

    numba checks only a function's own source file, but the kernels call
    across modules: an edit of `_lsap.py` would leave `_kernels.py`'s cached
    callers running the old code. (An install writes every file anew, which
    invalidates all caches anyway.)
    """
    here = Path(__file__).parent
    cache = here / "__pycache__"
    try:
        stats = [(here / f"{m}.py").stat() for m in KERNEL_MODULES]
        stamp = " ".join(f"{m}:{s.st_mtime_ns}:{s.st_size}" for m, s in zip(KERNEL_MODULES, stats))
        mark = cache / "kernels.stamp"
        if mark.is_file() and mark.read_text() == stamp:
            return
        for m in KERNEL_MODULES:
            for f in cache.glob(f"{m}.*.nb[ic]"):
                f.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        mark.write_text(stamp)
    except OSError:  # read-only install: nothing is cached in the tree
        pass


def njit(fn: Callable) -> Callable:
    """`numba.njit(cache=True)`; compiles in memory (no cache) if no cache directory is writable.

    numba caches next to the source or in the user's cache directory
    (NUMBA_CACHE_DIR overrides both); a read-only install without a writable
    home gets neither, and every process then compiles its kernels again.
    """
    try:
        return numba.njit(cache=True)(fn)
    except RuntimeError as exc:  # "cannot cache function ...: no locator available"
        global _warned
        if not _warned:
            _warned = True
            warnings.warn(f"numba kernels compile in memory, not cached: {exc}", RuntimeWarning, stacklevel=2)
        return numba.njit(fn)


_drop_stale_caches()
