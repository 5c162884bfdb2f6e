"""Solving long load sweeps in fixed-size chunks: one compilation, bounded memory, a progress bar."""

from __future__ import annotations

import jax
import numpy as np

from ..core import Outputs, Scene, Solution
from ..core._loadcontrol import DEFAULT_OUTPUTS, solve
from ..programs import bucket, edge_padded

CHUNK = 4096


def map_in_chunks(fn, values, *, chunk: int, progress: bool = False, desc: str = "", pad_small: bool = False):
    """`fn(values)` computed `chunk` values at a time, results concatenated along axis 0.

    The last chunk is padded by repeating its final value, so that a jitted `fn` is compiled
    once; `fn` returns a pytree of arrays. Leaves with a leading axis of the chunk's length are
    per value and concatenated; the others (a `Solution`'s E and A_a, say) are per call and taken
    from the first chunk. Fewer than `chunk` values go in one unpadded call unless `pad_small` (for
    callers whose blocks must always be `chunk` long, e.g. to divide evenly over devices).
    """
    values = np.asarray(values)
    if values.size <= chunk and not pad_small:
        return jax.tree.map(np.asarray, fn(values))
    starts = range(0, values.size, chunk)
    if progress:
        from tqdm.auto import tqdm

        starts = tqdm(starts, total=len(starts), unit="chunk", desc=desc)
    pieces, sizes = [], []
    for start in starts:
        block = values[start : start + chunk]
        pieces.append(jax.tree.map(np.asarray, fn(edge_padded(block, chunk))))
        sizes.append(block.size)

    def join(*xs):
        if xs[0].ndim == 0 or xs[0].shape[0] != chunk:
            return xs[0]
        return np.concatenate([x[:n] for x, n in zip(xs, sizes)])

    return jax.tree.map(join, *pieces)


def solve_sweep(
    scene: Scene,
    loads,
    *,
    outputs: Outputs = DEFAULT_OUTPUTS,
    chunk: int = CHUNK,
    progress: bool = False,
) -> Solution:
    """`solve(scene, loads, outputs=...)` for a 1-D array of loads, as numpy arrays,
    `chunk` loads at a time (one compilation, bounded memory); `progress=True` shows a tqdm bar."""
    loads = np.asarray(loads, dtype=float).reshape(-1)
    # Fewer loads than a chunk are padded here, on the host, to the length `solve` would pad them
    # to: the same program, and no program to cut its outputs back (one compilation fewer).
    small = 0 < loads.size <= chunk
    return map_in_chunks(
        lambda block: solve(scene, block, outputs=outputs),
        loads,
        chunk=bucket(loads.size) if small else chunk,
        pad_small=small,
        progress=progress,
        desc=f"solving {loads.size} loads",
    )
