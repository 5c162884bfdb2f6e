"""Parameter sweeps over a D × G × load grid, sharded across every JAX device.

The (D, G) pairs are laid along one mesh axis ("grid") of a `jax.sharding.Mesh` over
`jax.devices()`; each device solves its share of pairs for all loads. Inputs are built with
`jax.make_array_from_callback` and outputs gathered with `process_allgather`, so the same code
runs on one CPU, several GPUs, or several hosts after `jax.distributed.initialize()` (the CLI's
`--distributed`). Blocks of pairs are solved one after another (bounded memory, a progress bar).
"""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.experimental import multihost_utils
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from ..core import Scene, prepare, solve
from ._chunks import map_in_chunks


@dataclasses.dataclass(frozen=True)
class SweepResult:
    """Arrays of shape (len(D), len(G), len(loads)): stiffness (N/m), a_l (m²), status."""

    D: np.ndarray
    G: np.ndarray
    loads: np.ndarray
    stiffness: np.ndarray
    a_l: np.ndarray
    status: np.ndarray
    devices: int


def _solver(scene: Scene, loads, sharding):
    def one(D, G):
        sol = solve(eqx.tree_at(lambda s: (s.surface.D, s.surface.G), scene, (D, G)), loads)
        return sol.stiffness, sol.a_l, sol.status

    return jax.jit(jax.vmap(one), in_shardings=(sharding, sharding), out_shardings=sharding)


def sweep(scene: Scene, D, G, loads, *, block: int | None = None, progress: bool = False, devices=None) -> SweepResult:
    """Solve every (D, G) pair of the grid at every load, sharded across `devices` (default: all).

    **Arguments:**

    - `scene`: supplies everything but D and G.
    - `D`, `G`: 1-D arrays of fractal dimensions and roughnesses (m); the grid is their product.
    - `loads`: 1-D array of loads (N).
    - `block`: pairs per step (rounded up to a multiple of the device count; default 64 per device).
    """
    D, G = np.asarray(D, dtype=float).reshape(-1), np.asarray(G, dtype=float).reshape(-1)
    # The same checks as the scene's own fields, with a clear message for the first bad value.
    for d in D:
        eqx.tree_at(lambda s: s.surface.D, scene, float(d)).surface.__check_init__()
    for g in G:
        eqx.tree_at(lambda s: s.surface.G, scene, float(g)).surface.__check_init__()
    scene, loads = prepare(scene, np.asarray(loads, dtype=float).reshape(-1))
    devices = jax.devices() if devices is None else list(devices)
    mesh = Mesh(np.array(devices), ("grid",))
    sharding = NamedSharding(mesh, PartitionSpec("grid"))
    pairs_D, pairs_G = (x.reshape(-1) for x in np.meshgrid(D, G, indexing="ij"))
    n = pairs_D.size
    block = len(devices) * (64 if block is None else -(-block // len(devices)))
    run = _solver(scene, loads, sharding)
    dtype = loads.dtype

    def solve_block(pairs):
        inputs = [
            jax.make_array_from_callback((pairs.size,), sharding, lambda idx, x=x[pairs]: jnp.asarray(x[idx], dtype))
            for x in (pairs_D, pairs_G)
        ]
        return tuple(np.asarray(multihost_utils.process_allgather(x, tiled=True)) for x in run(*inputs))

    # Every block has exactly `block` pairs (the last padded), so its length divides over the devices.
    outputs = map_in_chunks(
        solve_block,
        np.arange(n),
        chunk=block,
        pad_small=True,
        progress=progress,
        desc=f"sweep: {n} (D, G) pairs × {loads.size} loads",
    )
    K, a_l, status = (x.reshape(D.size, G.size, loads.size) for x in outputs)
    return SweepResult(D=D, G=G, loads=np.asarray(loads), stiffness=K, a_l=a_l, status=status, devices=len(devices))
