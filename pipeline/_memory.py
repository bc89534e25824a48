"""Handing freed memory back to the system (glibc's ``malloc_trim``).

A long run that allocates and frees many buffers of a few hundred kB to a few MB — a
campaign's records, a joint fit's chunks of records sent to a cluster and their results —
leaves the C allocator holding the freed memory in its heaps, in pieces too scattered to
reuse, and the process's resident memory creeps up with the number of buffers made, not
with what it holds. :func:`release` returns the free pages to the system (glibc's
``malloc_trim(0)``, as dask's workers do with their trim threshold); where the C library
has none (macOS, Windows, musl) it only collects Python's cyclic garbage, if asked.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import gc

__all__ = ["release"]


@functools.cache
def _malloc_trim():
    """glibc's ``malloc_trim`` (None where the C library has none: macOS, Windows, musl)."""
    with contextlib.suppress(OSError, AttributeError, TypeError):
        return ctypes.CDLL(None).malloc_trim  # the process's own C library
    return None


def release(*, collect: bool = True) -> None:
    """Free Python's cyclic garbage (``collect``: a full collection, tens of ms in a large
    process) and hand the memory the allocator then holds free back to the system (a few
    ms)."""
    if collect:
        gc.collect()
    trim = _malloc_trim()
    if trim is not None:
        trim(0)
