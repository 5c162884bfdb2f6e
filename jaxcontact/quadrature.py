"""Fixed Gauss–Legendre quadrature in log-area.

Only the interaction stiffness needs it (every other integral of the model has a closed
form). Integrands span many decades of `a`, so the variable is `t = ln a`, in which they are
smooth and slowly varying.
"""

from __future__ import annotations

import functools

import jax.numpy as jnp
import numpy as np


@functools.lru_cache(maxsize=None)
def gauss_legendre(nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights on [-1, 1] (numpy's `leggauss`, computed once per node count)."""
    return np.polynomial.legendre.leggauss(nodes)


def integrate_log_area(integrand, log_lower, log_upper, nodes: int):
    """`∫ g(t) dt` over `[log_lower, log_upper]` (elementwise over the bounds' shape).

    **Arguments:**

    - `integrand`: `g(t)`, the integrand with respect to `t = ln a` (that is, `a · h(a)` for
      `∫ h(a) da`); called with `t` of shape `bounds.shape + (nodes,)`, it returns the same shape.
    - `log_lower`, `log_upper`: bounds, of equal shape; an empty interval gives 0.
    - `nodes`: number of Gauss–Legendre nodes per interval (static).
    """
    x, w = gauss_legendre(nodes)
    half = 0.5 * (log_upper - log_lower)[..., None]
    mid = 0.5 * (log_upper + log_lower)[..., None]
    t = mid + half * jnp.asarray(x, dtype=half.dtype)
    return jnp.sum(jnp.asarray(w, dtype=half.dtype) * integrand(t), axis=-1) * half[..., 0]
