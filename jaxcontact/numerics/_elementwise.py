"""Small array helpers that keep the per-point computations elementwise.

Under `vmap` a load point's regimes become a short minor axis (4 regimes, 3 with stiffness).
XLA on CPU emits a reduction or a gather over such an axis as a scalar loop, and every `exp`
fused into that loop then runs one value at a time; written as separate elementwise operations
on the batch axis the same work is vectorised (3x faster for 16 closed-form integrals per
point in a micro-benchmark).
"""

from __future__ import annotations

import jax
from jaxtyping import Array, ArrayLike, Float, Int


def pick(values: Float[Array, "n"], index: Int[ArrayLike, ""]) -> Float[Array, ""]:
    """`values[index]` as an elementwise select, which XLA fuses into the surrounding loop."""
    return jax.lax.select_n(index, *values)


def unrolled_sum(values: Float[Array, "... n"]) -> Float[Array, "..."]:
    """`values.sum(-1)` as a chain of elementwise additions (for a short last axis)."""
    total = values[..., 0]
    for k in range(1, values.shape[-1]):
        total = total + values[..., k]
    return total
