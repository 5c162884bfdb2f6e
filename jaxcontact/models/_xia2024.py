"""The model of Xia, Qu & Liu (Aerospace 11, 472, 2024): the integrals over the size distribution
(Sec. 4, Eqs. 30–39) of Kogut–Etsion asperities, small ones elastic, cut off at `a_min = l_min²`.

For a given largest spot `a_l`, each regime's interval is clipped to `(a_min, a_l]` and

    F_t(a_l) = Σ_{e,ep1,ep2,p} ∫ f(a) n(a) da        Eqs. (31)–(35)
    K_t(a_l) = Σ_{e,ep1,ep2}   ∫ k(a) n(a) da        Eqs. (36)–(39)
    A_r(a_l) = ∫ a n(a) da

`F_t` does not depend on the interaction (docs/model.md §4): the paper's Eq. (31) writes f through ω,
and with ω = a/(πR) that is Eq. (5) exactly. Without interaction all of these are power-law
integrals with closed forms; with interaction the stiffness is the closed form plus the
interaction's correction (`AbstractInteraction.corrections`).
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import NewtonBisection, PowerLaw, check_instance
from ..physics import (
    AbstractDistribution,
    AbstractInteraction,
    AbstractSpotStiffness,
    FamilyDerivative,
    MajumdarBhushan,
    PaperInteraction,
    interaction_ratio,
    interference,
    kogut_etsion_laws,
    regime_edges,
    size_distribution,
)
from ..quantities import DimensionlessScene
from ._base import JointResponse
from ._largest_spot import AbstractJoint, AbstractLargestSpotModel
from ._load_pieces import PowerLawLoadPieces
from ._spots import SpotFamilies

REGIMES = ("e", "ep1", "ep2", "p")
# Fully plastic asperities carry load but add no stiffness on loading (Sec. 4.2). Plain Python values,
# not jnp arrays: a module-level array would freeze the precision that was active at import.
_HAS_STIFFNESS = (1.0, 1.0, 1.0, 0.0)


class Xia2024(AbstractLargestSpotModel):
    """Xia, Qu & Liu (2024), docs/model.md §2–4: Kogut–Etsion regimes (e, ep1, ep2, p) over the
    Majumdar–Bhushan size distribution, with interaction between asperities.

    **Arguments:**

    - `interaction`: `PaperInteraction()` (the default, `ω = ξ - σ` as Eqs. 23–26 print),
      `SeriesInteraction()` (`ω = ξ + σ`) or `NoInteraction()`; the first two take the quadrature
      of their correction (`PaperInteraction(quadrature=GaussLegendre(32))`).
    - `distribution`: `MajumdarBhushan()` (Eq. 30, the default) or `WangKomvopoulos()`.
    - `spot_stiffness`: `FamilyDerivative()` (the default, Eqs. 27–29, `k = f'/ξ'`) or `Sneddon()`
      (`k = 2E√(a/π)`, one circular spot's stiffness; docs/model.md §9), divided by `1 ± r` alike.
    - `root_finder`: the a_l solve of each load, `NewtonBisection()` (64 steps at most, 64 ε).
    """

    name: ClassVar[str] = "xia2024"
    regimes: ClassVar[tuple[str, ...]] = REGIMES
    interaction: AbstractInteraction = PaperInteraction()
    distribution: AbstractDistribution = MajumdarBhushan()
    spot_stiffness: AbstractSpotStiffness = FamilyDerivative()
    # Keyword-only: the base class declares it first, and the choices keep their positions.
    root_finder: NewtonBisection = eqx.field(default=NewtonBisection(), kw_only=True)

    def __check_init__(self):
        check_instance("interaction", self.interaction, AbstractInteraction)
        check_instance("root_finder", self.root_finder, NewtonBisection)
        check_instance("distribution", self.distribution, AbstractDistribution)
        check_instance("spot_stiffness", self.spot_stiffness, AbstractSpotStiffness)

    def joint(self, s: DimensionlessScene) -> Xia2024Joint:
        load_laws, log_a_c = kogut_etsion_laws(s.D, s.log_G, s.log_hardness, s.nu)
        interference_law = interference(s.D, s.log_G)
        return Xia2024Joint(
            D=s.D,
            log_a_min=s.log_a_min,
            log_density=self.distribution.log_scale(s.D),
            edges=regime_edges(log_a_c),
            load_laws=load_laws,
            interference_law=interference_law,
            spot_law=self.spot_stiffness.law(load_laws, interference_law),
            interaction=self.interaction,
        )


class Xia2024Joint(AbstractJoint):
    """Xia, Qu & Liu (2024): Kogut–Etsion regimes, small asperities elastic, cutoff at `a_min`."""

    D: Float[Array, ""]
    log_a_min: Float[Array, ""]
    log_density: Float[Array, ""]
    edges: Float[Array, " 5"]
    load_laws: PowerLaw
    interference_law: PowerLaw
    spot_law: PowerLaw  # k(a) without interaction, per regime
    interaction: AbstractInteraction

    def intervals(self, log_a_l):
        """Each regime's range of `ln a`, clipped to `(ln a_min, ln a_l]`; empty ones have length 0."""
        lower = jnp.clip(self.edges[:-1], self.log_a_min, log_a_l)
        upper = jnp.clip(self.edges[1:], self.log_a_min, log_a_l)
        return lower, upper

    def distribution(self, log_a_l) -> PowerLaw:
        return size_distribution(self.D, log_a_l, self.log_density)

    def kinks(self):
        return self.edges[1:-1]

    def load_pieces(self) -> PowerLawLoadPieces:
        return PowerLawLoadPieces.build(self.knots(), self.D / 2.0, self.load_laws * self.distribution(0.0))

    def regime_load(self, log_a_l):
        """Eqs. (31)–(34): `∫ f(a) n(a) da` over each regime, in closed form."""
        lower, upper = self.intervals(log_a_l)
        return (self.load_laws * self.distribution(log_a_l)).integral(lower, upper)

    def regime_stiffness(self, log_a_l, log_load):
        """Eqs. (36)–(38): `∫ k(a) n(a) da` over each regime, and the breakdown flag.

        `k = k₀/(1 ± r)` (`k₀ = f'/ξ'`, or Sneddon's `2E√(a/π)`: `spot_law`): the closed form of
        `∫ k₀ n da` plus the interaction's correction (`AbstractInteraction.corrections`). Fully
        plastic spots add no stiffness on loading (Sec. 4.2).
        """
        return self._summed(self.spot_law, _HAS_STIFFNESS, log_a_l, log_load)

    def unloading_stiffness(self, log_a_l, log_load):
        """Each regime's initial unloading stiffness (docs/model.md §12): every spot unloads
        elastically, with the elastic regime's spot law at its contact area at the top (Sneddon's
        `2E√(a/π)` with `Sneddon()`, the paper's family factor times it with `FamilyDerivative()`),
        so that an all-elastic joint unloads as it loads; divided by `1 ± r` as on loading."""
        return self._summed(self._elastic_law(), (1.0,) * len(REGIMES), log_a_l, log_load)

    def spots(self, log_a_l, log_load) -> SpotFamilies:
        """Every regime's spots with the load law of the regime and the unloading law of
        `unloading_stiffness`; `r` as on loading (Eq. 22)."""
        lower, upper = self.intervals(log_a_l)
        count = self.distribution(log_a_l) * PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D))
        rows = PowerLaw(*(jnp.broadcast_to(x, lower.shape) for x in (count.log_coeff, count.exponent)))
        ratio = interaction_ratio(self.load_laws, self.interference_law, log_load)
        return SpotFamilies(rows, self.load_laws, self._elastic_law(), ratio, self.interaction, lower, upper)

    def _elastic_law(self) -> PowerLaw:
        """The elastic regime's spot law in every regime's row."""
        return jax.tree.map(lambda x: jnp.broadcast_to(x[0], x.shape), self.spot_law)

    def _summed(self, law: PowerLaw, has_stiffness: tuple[float, ...], log_a_l, log_load):
        """`∫ k₀ n /(1 ± r) da` per regime for the spot law `k₀ = law`, times `has_stiffness` (the
        regimes with stiffness first), and the breakdown flag."""
        lower, upper = self.intervals(log_a_l)
        integrand = law * self.distribution(log_a_l)
        closed_form = integrand.integral(lower, upper) * jnp.asarray(has_stiffness, lower.dtype)
        rows = slice(0, sum(1 for x in has_stiffness if x))
        density = PowerLaw(integrand.log_coeff[rows], integrand.exponent[rows] + 1.0)  # k₀ n a, in t = ln a
        corrections, breakdown = self.interaction.corrections(
            density, self.load_laws[rows], self.interference_law, log_load, lower[rows], upper[rows]
        )
        # Stacked, so that each regime stays its own elementwise chain (see `paper_correction`).
        parts = [closed_form[i] + c for i, c in enumerate(corrections)]
        return jnp.stack(parts + [closed_form[i] for i in range(len(parts), len(REGIMES))]), breakdown

    def real_area(self, log_a_l):
        """`A_r* = ∫ a n(a) da` over `(a_min, a_l]`, all regimes."""
        area_law = self.distribution(log_a_l) * PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D))
        return area_law.integral(self.log_a_min, jnp.maximum(log_a_l, self.log_a_min))

    def response(self, log_a_l, log_load):
        stiffness, breakdown = self.regime_stiffness(log_a_l, log_load)
        return JointResponse(self.regime_load(log_a_l), stiffness, self.real_area(log_a_l), breakdown)
