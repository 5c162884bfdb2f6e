"""One registry of the library's in-memory caches, and `clear_caches()` (as `equinox.clear_caches`).

Every cache of the library is made here (`cached`) or registered (`register_cache`), so that one
call drops them all: compiled programs, their load buckets, kernels and memo tables. Nothing on
disk is touched (the command line's kept programs, the BEM's result cache).
"""

from __future__ import annotations

import functools
from collections.abc import Callable

_CLEARERS: list[Callable[[], None]] = []


def register_cache(clear: Callable[[], None]) -> Callable[[], None]:
    """Make `clear` (which empties one cache) part of `clear_caches()`; returns it."""
    _CLEARERS.append(clear)
    return clear


def cached(function: Callable | None = None, *, maxsize: int | None = None):
    """`functools.lru_cache(maxsize)` (unbounded by default), registered with `clear_caches`."""

    def wrap(function: Callable):
        memo = functools.lru_cache(maxsize=maxsize)(function)
        register_cache(memo.cache_clear)
        return memo

    return wrap if function is None else wrap(function)


def clear_caches() -> None:
    """Drop every in-memory cache of jaxcontact: its compiled programs (recompiled on next use),
    kernels and memo tables. JAX's own caches are JAX's (`jax.clear_caches()`)."""
    for clear in _CLEARERS:
        clear()
