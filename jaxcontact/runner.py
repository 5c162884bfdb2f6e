"""Solving long load sweeps in fixed-size chunks: one compilation, bounded memory, a progress bar."""

from __future__ import annotations

import jax
import numpy as np

from .scene import Scene
from .solution import Solution
from .solve import solve

CHUNK = 4096


def solve_sweep(scene: Scene, loads, *, chunk: int = CHUNK, progress: bool = False) -> Solution:
    """`solve(scene, loads)` for a 1-D array of loads, as numpy arrays.

    Loads are solved `chunk` at a time (the last chunk padded by repeating its final load, so
    that every call reuses one compiled program); `progress=True` shows a tqdm bar.
    """
    loads = np.asarray(loads, dtype=float).reshape(-1)
    if loads.size <= chunk:
        return jax.tree.map(np.asarray, solve(scene, loads))
    pieces = []
    starts = range(0, loads.size, chunk)
    if progress:
        from tqdm.auto import tqdm

        starts = tqdm(starts, total=len(starts), unit="chunk", desc=f"solving {loads.size} loads")
    for start in starts:
        block = loads[start:start + chunk]
        padded = np.pad(block, (0, chunk - block.size), mode="edge")
        sol = jax.tree.map(np.asarray, solve(scene, padded))
        pieces.append(jax.tree.map(lambda x, n=block.size: x[:n], sol))
    return jax.tree.map(lambda *xs: np.concatenate(xs), *pieces)
