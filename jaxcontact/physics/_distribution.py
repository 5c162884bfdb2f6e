"""The asperity size distribution (Eq. 30) and its Wang–Komvopoulos correction."""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp

from ..numerics import PowerLaw, solve_increasing

# ψ at the ends of 1 < D < 2, where its equation has closed-form roots: the golden ratio squared
# (D → 1, where it is a quadratic in √ψ) and e - 1 (D → 2, where it becomes ln(1 + ψ) = 1).
_PSI_AT_D1 = ((1.0 + math.sqrt(5.0)) / 2.0) ** 2
_PSI_AT_D2 = math.e - 1.0
# Newton steps from the straight line between those ends; the line is within 0.2 of ψ and five
# steps reach round-off for every 1 < D < 2 (tests/test_distribution.py checks a dense grid).
_PSI_STEPS = 5


def _wk_residual(psi, D):
    # The equation `(ψ^((2-D)/2) - (1 + ψ^(-D/2))^(-x)) / x = 1`, x = (2-D)/D, with both powers
    # written as expm1: as D → 2 they both tend to 1 and the plain difference loses every digit
    # (at D = 1.999 Newton's method could no longer meet a round-off tolerance).
    x = (2.0 - D) / D
    half_log = 0.5 * D * jnp.log(psi)  # ln ψ^(D/2)
    return (jnp.expm1(x * half_log) - jnp.expm1(-x * jnp.log1p(jnp.exp(-half_log)))) / x - 1.0, None


def wang_komvopoulos_psi(D):
    """Domain-extension factor ψ > 1 of Wang & Komvopoulos (docs/model.md §4).

    Solves `(ψ^((2-D)/2) - (1 + ψ^(-D/2))^(-(2-D)/D)) / ((2-D)/D) = 1`, whose left side
    increases in ψ, by a fixed number of Newton steps clipped to `[1, 4]` (straight-line code:
    no loop to compile), differentiated implicitly in D. ψ falls from `φ² = 2.618`
    (D → 1) through 2.0007 (D = 1.5) to `e - 1 = 1.718` (D → 2).

    **Arguments:** `D`, the fractal dimension, `1 < D < 2` (any shape: `vmap` for arrays).

    **Returns:** ψ(D).
    """
    D = jnp.asarray(D)
    guess = _PSI_AT_D1 + (_PSI_AT_D2 - _PSI_AT_D1) * (D - 1.0)
    tolerance = float(64 * jnp.finfo(D.dtype).eps)
    psi, _ = solve_increasing(
        _wk_residual,
        guess,
        D,
        jnp.ones_like(D),
        jnp.full_like(D, 4.0),
        tolerance=tolerance,
        max_steps=_PSI_STEPS,
        unrolled_steps=_PSI_STEPS,
    )
    return psi


class AbstractDistribution(eqx.Module):
    """The asperity size distribution's normalisation: `n(a) = e^(log_scale) (D/2) a_l^(D/2) a^(-(D+2)/2)`.

    A choice, passed to a model as an object (`Xia2024(distribution=WangKomvopoulos())`).
    """

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def log_scale(self, D):
        """`ln` of the factor multiplying the Majumdar–Bhushan n(a) of Eq. (30)."""


class MajumdarBhushan(AbstractDistribution):
    """Eq. (30) as printed: `n(a) = (D/2) a_l^(D/2) a^(-(D+2)/2)`."""

    name: ClassVar[str] = "mb"

    def log_scale(self, D):
        return jnp.zeros_like(jnp.asarray(D))


class WangKomvopoulos(AbstractDistribution):
    """Eq. (30) times the domain-extension factor `ψ^((2-D)/2)` of Wang & Komvopoulos (docs/model.md §4)."""

    name: ClassVar[str] = "wk"

    def log_scale(self, D):
        return (2.0 - D) / 2.0 * jnp.log(wang_komvopoulos_psi(D))


def size_distribution(D, log_a_l, log_scale) -> PowerLaw:
    """Size distribution of contact spots, Eq. (30): `n(a) = (D/2) a_l^(D/2) a^(-(D+2)/2)`.

    `n(a) da` is a count, so it is the same in dimensionless areas. `log_scale` is the
    distribution's `log_scale` (0 for the plain MB distribution).
    """
    return PowerLaw(jnp.log(D / 2.0) + D / 2.0 * log_a_l + log_scale, -(D + 2.0) / 2.0)
