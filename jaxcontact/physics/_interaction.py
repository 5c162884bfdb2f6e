"""Interaction between asperities (Sec. 3) and the stiffness of one asperity (Eqs. 22–29).

The load `f` of an asperity, spread at the nominal pressure `P_m = F/A_a`, settles the
substrate under it by (Eq. 22)

    σ(a) = 1.12 √(f(a) P_m) / E          (1.12 ≈ 2/√π: centre of a uniformly loaded circle)

and the asperity's deformation is `ω = ξ ± σ`. The paper's Eqs. (23)–(26) print `ξ - σ`
(interaction "paper", which makes the joint *stiffer*, as its Fig. 6 shows); its conclusion (3)
says interaction lowers the stiffness, which is `ξ + σ` (interaction "series"). docs/model.md §3
offers both, and "none" (`ω = ξ`) as the comparator.

In dimensionless form (lengths in `sqrt(A_a)`, pressure in `E`) `σ* = 1.12 √(f* F*)`.
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from ..numerics import (
    AbstractQuadrature,
    AbstractRowQuadrature,
    GaussLegendre,
    InputError,
    PowerLaw,
    PowerSeries,
    check_instance,
)
from ..numerics._interaction_integral import paper_correction, series_correction

SETTLEMENT_COEFFICIENT = 1.12


class AbstractInteraction(eqx.Module):
    """How the substrate settlement σ enters the asperity's deformation: `ω = ξ + sign · σ`, and
    what that does to the joint's stiffness (`corrections`).

    A choice, passed to a model as an object (`Xia2024(interaction=SeriesInteraction())`); it
    holds no arrays, so changing it compiles a different program and nothing is traced.
    """

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def corrections(
        self, density: PowerLaw, load_laws: PowerLaw, interference_law: PowerLaw, log_load, lower, upper
    ) -> tuple[list[Float[Array, ""]], Bool[Array, ""]]:
        """The interaction's part of each regime's stiffness, and whether the model breaks down.

        **Arguments:** the regimes with stiffness, one row each: `density`, `k₀ n a` as a law in
        `t = ln a` (`k₀` the asperity's stiffness without interaction); `load_laws` f(a) and the
        `interference_law` ξ(a) (Eqs. 5–15), which set `r = σ'/ξ'` at the nominal pressure
        `F* = e^log_load` (Eq. 22); `lower`, `upper`, the rows' ranges of `ln a*`.

        **Returns:** `∫ k₀ n (1/(1 ± r) - 1) da` per row (a list of scalars: each row its own
        chain of operations, `interaction_integral`), and the breakdown flag (`ω'` vanishing
        inside a range: the model is not valid at this load).
        """

    @abc.abstractmethod
    def spot_factor(self, ratio):
        """`k/k₀` of one spot whose `r = σ'/ξ'` is `ratio`: `1/(1 ± r)`, or 1 without interaction."""


class NoInteraction(AbstractInteraction):
    """`ω = ξ`: the no-interaction comparator of the paper's Fig. 6. No correction, and nothing of
    the nominal pressure reaches the stiffness."""

    name: ClassVar[str] = "none"

    def corrections(self, density, load_laws, interference_law, log_load, lower, upper):
        del density, load_laws, interference_law, log_load, upper
        return [jnp.zeros_like(lower[i]) for i in range(lower.shape[0])], jnp.array(False)

    def spot_factor(self, ratio):
        return jnp.ones_like(ratio)


class PaperInteraction(AbstractInteraction):
    """`ω = ξ - σ`, Eqs. (23)–(26) as printed: a stiffer joint (Fig. 6), with a breakdown load.

    **Arguments:** `quadrature`, how the pole term `r/(1 - r)` is integrated: `PowerSeries()` (the
    default, summed to round-off, no nodes), `GaussLegendre(nodes)` or `Adaptive(tolerance)`.
    """

    name: ClassVar[str] = "paper"
    quadrature: AbstractQuadrature = PowerSeries()

    def __check_init__(self):
        check_instance("quadrature", self.quadrature, AbstractQuadrature)

    def corrections(self, density, load_laws, interference_law, log_load, lower, upper):
        ratio = interaction_ratio(load_laws, interference_law, log_load)
        breakdown = jnp.any((upper > lower) & (breakdown_log_area(ratio) <= upper))
        # At a breakdown point the value is discarded; a tiny ratio keeps every number (and
        # gradient) finite, so that one bad point cannot poison the gradient of a batch.
        ratio = PowerLaw(jnp.where(breakdown, -200.0, ratio.log_coeff), ratio.exponent)
        return paper_correction(density, ratio, lower, upper, self.quadrature), breakdown

    def spot_factor(self, ratio):
        return 1.0 / (1.0 - ratio)


class SeriesInteraction(AbstractInteraction):
    """`ω = ξ + σ`: settlement in series with the asperity, a softer joint (the paper's conclusion 3).

    **Arguments:** `quadrature`, a rule for the bounded integrand `-r/(1 + r)`: `GaussLegendre(nodes)`
    (the default, 16 nodes) or `Adaptive(tolerance)`.
    """

    name: ClassVar[str] = "series"
    quadrature: AbstractRowQuadrature = GaussLegendre()

    def __check_init__(self):
        if not isinstance(self.quadrature, AbstractRowQuadrature):
            raise InputError(
                f"quadrature = {self.quadrature!r} cannot integrate the 'series' interaction: it takes "
                "GaussLegendre() or Adaptive() ('gauss-legendre' or 'adaptive'); PowerSeries() is for 'paper' only"
            )

    def corrections(self, density, load_laws, interference_law, log_load, lower, upper):
        ratio = interaction_ratio(load_laws, interference_law, log_load)
        part = series_correction(density, ratio, lower, upper, self.quadrature)
        return [part[i] for i in range(lower.shape[0])], jnp.array(False)

    def spot_factor(self, ratio):
        return 1.0 / (1.0 + ratio)


def settlement(load_law: PowerLaw, log_load) -> PowerLaw:
    """Substrate settlement under an asperity, Eq. (22): `σ*(a) = 1.12 √(f*(a) P*)`, with `P* = F*`."""
    return (load_law.scaled(log_load)).sqrt().scaled(math.log(SETTLEMENT_COEFFICIENT))


def interaction_ratio(load_law: PowerLaw, interference_law: PowerLaw, log_load) -> PowerLaw:
    """`r(a) = σ'(a) / ξ'(a)`, so that `ω'(a) = ξ'(a) (1 ± r(a))`.

    Its exponent `(m + D)/2 - 1` is positive in every regime, so `r` grows with `a`.
    """
    return settlement(load_law, log_load).derivative() / interference_law.derivative()


def breakdown_log_area(ratio: PowerLaw):
    """`ln` of the area where `ω' = ξ' - σ'` vanishes (interaction "paper"): `r(a) = 1`.

    Closed form, since `r` is a power law in each regime. Past it, the paper's stiffness
    integrand `f'/ω'` has a pole and then changes sign: the model is no longer valid.
    """
    return -ratio.log_coeff / ratio.exponent


def stiffness_without_interaction(load_law: PowerLaw, interference_law: PowerLaw) -> PowerLaw:
    """Asperity stiffness with `ω = ξ`, Eqs. (27)–(29): `k(a) = f'(a) / ξ'(a)`."""
    return load_law.derivative() / interference_law.derivative()
