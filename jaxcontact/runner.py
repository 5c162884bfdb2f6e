"""Solving long load sweeps in fixed-size chunks: one compilation, bounded memory, a progress bar."""

from __future__ import annotations

import jax
import numpy as np

from .scene import Scene
from .solution import Solution
from .solve import solve

CHUNK = 4096


def map_in_chunks(fn, values, *, chunk: int, progress: bool = False, desc: str = "", pad_small: bool = False):
    """`fn(values)` computed `chunk` values at a time, results concatenated along axis 0.

    The last chunk is padded by repeating its final value, so that a jitted `fn` is compiled
    once; `fn` must return a pytree of arrays with a leading axis of the chunk's length.
    Fewer than `chunk` values go in one unpadded call unless `pad_small` (for callers whose
    blocks must always be `chunk` long, e.g. to divide evenly over devices).
    """
    values = np.asarray(values)
    if values.size <= chunk and not pad_small:
        return jax.tree.map(np.asarray, fn(values))
    starts = range(0, values.size, chunk)
    if progress:
        from tqdm.auto import tqdm

        starts = tqdm(starts, total=len(starts), unit="chunk", desc=desc)
    pieces = []
    for start in starts:
        block = values[start:start + chunk]
        result = jax.tree.map(np.asarray, fn(np.pad(block, (0, chunk - block.size), mode="edge")))
        pieces.append(jax.tree.map(lambda x, n=block.size: x[:n], result))
    return jax.tree.map(lambda *xs: np.concatenate(xs), *pieces)


def solve_sweep(scene: Scene, loads, *, chunk: int = CHUNK, progress: bool = False) -> Solution:
    """`solve(scene, loads)` for a 1-D array of loads, as numpy arrays, `chunk` loads at a time
    (one compilation, bounded memory); `progress=True` shows a tqdm bar."""
    loads = np.asarray(loads, dtype=float).reshape(-1)
    return map_in_chunks(lambda block: solve(scene, block), loads, chunk=chunk, progress=progress,
                         desc=f"solving {loads.size} loads")
