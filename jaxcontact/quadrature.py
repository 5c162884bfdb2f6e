"""Fixed Gauss–Legendre quadrature in log-area.

Only the interaction stiffness needs it (every other integral of the model has a closed
form). Integrands span many decades of `a`, so the variable is `t = ln a`, in which they are
smooth and slowly varying.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np
import quadax

QUADRATURES = ("power-series", "gauss-legendre", "adaptive")


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


def integrate_rows(integrand, row_args, log_lower, log_upper, *, method: str, nodes: int, tolerance: float):
    """`∫ integrand(t, *row_args[i]) dt` over `[log_lower[i], log_upper[i]]`, one result per row.

    **Arguments:**

    - `integrand`: elementwise in `t` and in the row arguments (it broadcasts).
    - `row_args`: tuple of arrays with one entry per row (the regime's coefficients); scalars
      for a single row.
    - `method`: "gauss-legendre" (fixed `nodes` per row, the default) or "adaptive" (quadax's
      Gauss–Kronrod `quadgk`, to relative `tolerance`, vectorised over the rows).
    """
    if method == "gauss-legendre":
        expanded = tuple(a[..., None] for a in row_args)
        return integrate_log_area(lambda t: integrand(t, *expanded), log_lower, log_upper, nodes)
    nonempty = log_upper > log_lower
    upper = jnp.where(nonempty, log_upper, log_lower + 1.0)  # quadgk wants a proper interval

    def one_row(lo, hi, *args):
        value, _ = quadax.quadgk(integrand, jnp.stack([lo, hi]), args=args, epsabs=0.0, epsrel=tolerance,
                                 max_ninter=100)
        return value

    return jnp.where(nonempty, jnp.vectorize(one_row)(log_lower, upper, *row_args), 0.0)
