"""Giving freed memory back to the system after a big job's temporaries.

glibc keeps what Python and numpy free on its heap for later allocations; after a big
mesh's working arrays (meshoptimizer's, an OBJ's blocks of text and corners) that is
hundreds of MB the process keeps resident but never uses again, since big arrays are
mapped afresh: the next stage's peak comes on top of it. malloc_trim(0) hands the free
pages back (glibc 2.8 and later trim the whole heap, not only its top)."""

from __future__ import annotations


def return_freed_memory() -> None:
    """malloc_trim(0) where the C library is glibc; nothing elsewhere."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):  # not glibc: nothing to do
        pass
