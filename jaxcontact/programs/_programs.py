"""One compiled program per static configuration, reused by every eager call.

An eager `jc.solve(scene, loads)` should cost what `jax.jit(solve)` on the scene's array leaves
costs. Two things stand in the way: `eqx.filter_jit` partitions the whole pytree on every call,
and XLA compiles a new program for every new length of the load array (seconds, against a
fraction of a millisecond to run it). So the program is a plain `jax.jit` of the scene's leaves,
one per tree structure (the static choices: model, interaction, quadrature, ...), and concrete
load arrays (a single load too) are padded to a few bucket lengths: a user who calls with 1, 7,
30 and 200 loads compiles the solve twice (32 and 224), and only a cheap slice per length.
Where a store other than this process's is active (`kept_in`: the command line keeps programs on
disk), a top-level call takes its program from there, so that a new process does not trace it again.
"""

from __future__ import annotations

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np

from ..numerics import cached, register_cache
from ..numerics._compat import staging, top_level
from . import _store as store

SMALLEST_BUCKET = 32
QUARTERS_FROM = 128


def bucket(size: int) -> int:
    """The padded length for `size` loads: the next power of two ≥ 32 up to 128, and above that
    the next of 2^k · (5/4, 6/4, 7/4, 2).

    Below 128 loads an eager call's cost is dispatch, not arithmetic (one load or 32: ~0.2 ms
    either way on "paper"), and one length per octave keeps compilations few; above, padding
    costs arithmetic (up to 2x at a power of two), and quarter octaves bound it to 1.25x for at
    most four compilations per octave.
    """
    if size == 0:
        return 0
    if size <= QUARTERS_FROM:
        return max(SMALLEST_BUCKET, 1 << (size - 1).bit_length())
    quarter = 1 << ((size - 1).bit_length() - 3)  # an eighth of the next power of two ≥ size
    return -(-size // quarter) * quarter


class _Program:
    """`function(tree, loads)` jitted over the tree's leaves, returning its outputs' leaves (and
    keeping their structure, known once traced), so that an eager call flattens nothing twice."""

    def __init__(self, function, treedef):
        self.output_tree = None
        self.roles = {}
        self.on_disk = {}
        self.name = f"{function.__module__}.{function.__qualname__}"
        self.treedef = treedef

        def flat(leaves, loads):
            outputs, self.output_tree = jax.tree_util.tree_flatten(
                function(jax.tree_util.tree_unflatten(treedef, leaves), loads)
            )
            return outputs

        def inline(leaves, loads):
            # As `jit` takes them: host values (a numpy load array, Python floats) become JAX arrays.
            return flat(*jax.tree_util.tree_map(jnp.asarray, (leaves, loads)))

        self.function = flat
        self.inline = inline
        self.flat = jax.jit(flat)

    def run(self, leaves, loads):
        """The outputs' leaves for concrete arguments, at top level: from the current store where one
        other than this process's is active (the command line's on disk: a new process need not
        trace it).

        A store for processes that make a few calls per program says below how many loads a program
        is compiled for a short compile time (`short_compile_below`; `compiling.FastCompile`:
        "paper", 64 loads, 1.6-1.8 s instead of 2.8 s, the same run time), its executable kept as
        well (`AbstractProgramStore.executable`); a full chunk of a long sweep keeps XLA's default,
        whose loops run 4096 loads 2x faster.
        """
        if not store.keeping():
            return self.flat(leaves, loads)
        kept = store.current_store()
        # Leaves are scalars but for a model's tables (a measured spectrum, summit heights), whose
        # lengths vary from scene to scene of one structure: a compiled program holds one length.
        key = (kept, loads.shape, loads.dtype, tuple(jnp.shape(leaf) for leaf in leaves))
        if key not in self.on_disk:
            args = ("solve", self.name, self.function, (leaves, loads))
            if loads.size < kept.short_compile_below:  # its executable is kept too: nothing to lower
                self.on_disk[key] = kept.executable(*args, closed_over=(self.treedef,))
            else:
                self.on_disk[key] = kept.program(*args, closed_over=(self.treedef,), fast_compile=False)
        return self.on_disk[key](leaves, loads)


def _output_tree(compiled: _Program, output_tree, leaves):
    if compiled.output_tree is None:  # read from disk: never traced in this process
        compiled.output_tree = output_tree(leaves)
    return compiled.output_tree


@cached(maxsize=64)
def program(function, treedef) -> _Program:
    """The cached program of `function` for trees of structure `treedef`."""
    return _Program(function, treedef)


@functools.partial(jax.jit, static_argnums=1)
def _pad(values, size):
    flat = values.reshape(-1)
    return jnp.concatenate([flat, jnp.broadcast_to(flat[-1], (size - flat.size,))])


def edge_padded(values: np.ndarray, size: int) -> np.ndarray:
    """Host `values` (non-empty) padded along their first axis to `size` by repeating the last.

    What `np.pad(values, (0, n), mode="edge")` gives a 1-D array, without its argument handling
    (200 loads: 1.4 µs against 13.6 µs, of an eager solve's ~0.3 ms).
    """
    out = np.empty((size, *values.shape[1:]), values.dtype)
    out[: len(values)] = values
    out[len(values) :] = values[-1]
    return out


# The JAX load array last padded at top level, and its padded copy: a caller's loop over scenes at one
# array of loads pads it once. JAX arrays are immutable, and the strong reference kept here makes
# the identity test sound.
_last_padded: list = [None, None]


@register_cache
def _forget_padded() -> None:
    _last_padded[:] = [None, None]


def padded(loads):
    """Concrete `loads`, flattened and padded to their bucket by repeating the last load; traced
    or already a bucket long, as they are."""
    size = bucket(loads.size)
    if isinstance(loads, jax.core.Tracer) or size == loads.size:
        return loads
    if isinstance(loads, np.ndarray):  # on the host already: padded there (as `map_in_chunks` pads)
        return edge_padded(loads.reshape(-1), size)
    if _last_padded[0] is loads:
        return _last_padded[1]
    result = _pad(loads, size)
    if top_level():  # a concrete array padded inside a caller's trace is that trace's value
        _last_padded[:] = [loads, result]
    return result


@cached(maxsize=256)
def _unpad(size: int, shape: tuple[int, ...]):
    """One jitted cut of the padded per-load outputs back to `shape`, and the per-call outputs
    reshaped to broadcast against it (one dispatch for all of them)."""
    count = math.prod(shape)

    def cut(per_load, per_call):
        per_load = [x[:count].reshape(shape + x.shape[1:]) for x in per_load]
        return per_load, [x.reshape((1,) * len(shape)) for x in per_call]

    return jax.jit(cut)


def unpadded(per_load, size: int, shape: tuple[int, ...]) -> list:
    """Per-load outputs of a call on `padded` loads (leading axis `size`) cut back to the loads' `shape`."""
    return _unpad(size, shape)(list(per_load), [])[0]


def _roles(compiled: _Program, size: int, ndim: int, outputs) -> tuple[list[int], list[int]]:
    """Which outputs are per load (leading axis `size`) and which per call, once per program and
    bucket: reading every output's shape costs more than the cut itself."""
    key = (size, ndim)
    if key not in compiled.roles:
        per_load = [i for i, x in enumerate(outputs) if x.ndim and x.shape[0] == size]
        # Per-call outputs are already shaped (1,) for 1-D loads: passed through untouched.
        per_call = [i for i in range(len(outputs)) if i not in per_load and ndim != 1]
        compiled.roles[key] = (per_load, per_call)
    return compiled.roles[key]


def call(function, leaves, treedef, loads, output_tree, pad: bool = True):
    """`function(tree, loads)`, for the tree of these leaves, through its cached program; concrete
    loads padded to a bucket.

    Per-load outputs have a leading axis of the loads' flattened length, and per-call outputs
    shape `(1,)`; both come back shaped as `function` gives them for `loads` itself. Inside a trace
    (the caller's own `jit`, `grad` or `vmap`) nothing is padded. `output_tree(leaves)` gives the
    outputs' tree structure where the program was read from disk, not traced.
    """
    compiled = program(function, treedef)
    # Inside a caller's staged program the function is traced into it directly: a nested `jit` is
    # transformed by re-tracing its program once per transformation (the fit's Jacobian: a third of
    # its tracing time). An eager `grad` or `vmap` calls the jitted program, which runs compiled.
    run = compiled.run if top_level() else compiled.inline if staging() else compiled.flat
    padded_loads = padded(loads) if pad else loads
    if padded_loads is loads:
        outputs = run(leaves, loads)
        return jax.tree_util.tree_unflatten(_output_tree(compiled, output_tree, leaves), outputs)
    size = padded_loads.size
    outputs = run(leaves, padded_loads)
    _output_tree(compiled, output_tree, leaves)
    per_load, per_call = _roles(compiled, size, loads.ndim, outputs)
    cut_load, cut_call = _unpad(size, loads.shape)([outputs[i] for i in per_load], [outputs[i] for i in per_call])
    for i, x in zip(per_load + per_call, cut_load + cut_call):
        outputs[i] = x
    return jax.tree_util.tree_unflatten(compiled.output_tree, outputs)
