"""The asperity size distribution (Eq. 30) and its Wang–Komvopoulos correction."""

from __future__ import annotations

import jax.numpy as jnp
import optimistix as optx

from .powerlaw import PowerLaw

DISTRIBUTIONS = ("mb", "wk")


def _wk_residual(psi, D):
    x = (2.0 - D) / D
    return (psi ** ((2.0 - D) / 2.0) - (1.0 + psi ** (-D / 2.0)) ** (-x)) / x - 1.0


def wang_komvopoulos_psi(D):
    """Domain-extension factor ψ > 1 of Wang & Komvopoulos (MODEL.md §4).

    Solves `(ψ^((2-D)/2) - (1 + ψ^(-D/2))^(-(2-D)/D)) / ((2-D)/D) = 1` by Newton's method
    (optimistix), differentiated implicitly in D. ψ ≈ 2.0848 at D = 1.4, ≈ 2.0007 at D = 1.5,
    and stays within (1.7, 2.7) over 1 < D < 2, so Newton from 2 converges everywhere.
    """
    D = jnp.asarray(D)
    eps = jnp.finfo(D.dtype).eps
    solver = optx.Newton(rtol=float(64 * eps), atol=float(64 * eps))
    sol = optx.root_find(_wk_residual, solver, jnp.full_like(D, 2.0), args=D, max_steps=64)
    return sol.value


def log_density_scale(D, distribution: str):
    """`ln` of the factor multiplying n(a): 0 for "mb", `((2-D)/2) ln ψ` for "wk"."""
    if distribution == "mb":
        return jnp.zeros_like(jnp.asarray(D))
    return (2.0 - D) / 2.0 * jnp.log(wang_komvopoulos_psi(D))


def size_distribution(D, log_a_l, log_scale) -> PowerLaw:
    """Size distribution of contact spots, Eq. (30): `n(a) = (D/2) a_l^(D/2) a^(-(D+2)/2)`.

    `n(a) da` is a count, so it is the same in dimensionless areas. `log_scale` is the
    Wang–Komvopoulos factor from `log_density_scale` (0 for the plain MB distribution).
    """
    return PowerLaw(jnp.log(D / 2.0) + D / 2.0 * log_a_l + log_scale, -(D + 2.0) / 2.0)
