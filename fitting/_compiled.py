"""fitting's own compiled programs (the batch fit; the sampler's adaptation and draws): each compiled
once per configuration and argument shapes and kept for the process (`jaxcontact.clear_caches()`
drops them), so that a second batch or a second posterior of the same shape compiles nothing."""

from __future__ import annotations

import time
from collections.abc import Callable

import equinox as eqx
import jax

from jaxcontact.numerics import register_cache


def compiled(function: Callable, *args):
    """`(program, dynamic, seconds)`: `function` compiled for `args` (their arrays traced, everything
    else, modules' static fields and plain functions included, part of the program), to be called as
    `program(dynamic)`; `seconds` spent compiling it, 0 where it was kept from an earlier call."""
    dynamic, static = eqx.partition(args, eqx.is_array)
    leaves, treedef = jax.tree_util.tree_flatten(dynamic)
    kept, kept_def = jax.tree_util.tree_flatten(static)
    shapes = tuple((x.shape, x.dtype, getattr(x, "weak_type", False)) for x in leaves)
    key = (function, kept_def, tuple(kept), treedef, shapes)
    seconds = 0.0
    if key not in _PROGRAMS:
        t0 = time.perf_counter()
        _PROGRAMS[key] = jax.jit(lambda d: function(*eqx.combine(d, static))).lower(dynamic).compile()
        seconds = time.perf_counter() - t0
    return _PROGRAMS[key], dynamic, seconds


_PROGRAMS: dict = {}
register_cache(_PROGRAMS.clear)
