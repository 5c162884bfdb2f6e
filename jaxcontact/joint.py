"""The joint: the integrals over the size distribution (Sec. 4, Eqs. 30–39), for model "xia2024".

For a given largest spot `a_l`, each regime's interval is clipped to `(a_min, a_l]` and

    F_t(a_l) = Σ_{e,ep1,ep2,p} ∫ f(a) n(a) da        Eqs. (31)–(35)
    K_t(a_l) = Σ_{e,ep1,ep2}   ∫ k(a) n(a) da        Eqs. (36)–(39)
    A_r(a_l) = ∫ a n(a) da

`F_t` does not depend on the interaction (MODEL.md §4): the paper's Eq. (31) writes f through ω,
and with ω = a/(πR) that is Eq. (5) exactly. Without interaction all of these are power-law
integrals with closed forms. With interaction the stiffness is the closed form plus a correction
`∫ k₀ n (1/(1 ± r) - 1) da`, the only integral done by quadrature (in log-area), so that the
quadrature error only touches the (usually small) interaction part.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from .asperity import interference, regime_edges, regime_load_laws
from .dimensionless import DimensionlessScene
from .distribution import size_distribution
from .interaction import INTERACTION_SIGNS, breakdown_log_area, interaction_ratio, stiffness_without_interaction
from .powerlaw import PowerLaw
from .quadrature import integrate_rows

# Fully plastic asperities carry load but add no stiffness (Sec. 4.2). Plain Python values,
# not jnp arrays: a module-level array would freeze the precision that was active at import.
_HAS_STIFFNESS = (1.0, 1.0, 1.0, 0.0)


class JointResponse(eqx.Module):
    """Totals of the joint at one `a_l` (dimensionless), split by regime (e, ep1, ep2, p).

    **Fields:** `regime_load` (F* per regime), `regime_stiffness` (K* per regime), `real_area`
    (A_r*), `breakdown` (True where the "paper" interaction's ω' vanishes inside the range).
    """

    regime_load: Float[Array, "4"]
    regime_stiffness: Float[Array, "4"]
    real_area: Float[Array, ""]
    breakdown: Bool[Array, ""]


class AbstractJoint(eqx.Module):
    """A load–area–stiffness model of the whole joint as a function of `ln a_l*`."""

    log_a_min: eqx.AbstractVar[Float[Array, ""]]

    @abc.abstractmethod
    def regime_load(self, log_a_l) -> Float[Array, "4"]:
        """Dimensionless load carried in each regime (e, ep1, ep2, p)."""

    def total_load(self, log_a_l):
        """`F_t*(a_l)`, Eq. (35); increasing in `a_l`."""
        return jnp.sum(self.regime_load(log_a_l))

    @abc.abstractmethod
    def response(self, log_a_l, log_load) -> JointResponse:
        """Everything at the solved `a_l`; `log_load = ln F*` sets the nominal pressure."""


class Xia2024Joint(AbstractJoint):
    """Xia, Qu & Liu (2024): Kogut–Etsion regimes, small asperities elastic, cutoff at `a_min`."""

    D: Float[Array, ""]
    log_a_min: Float[Array, ""]
    log_density: Float[Array, ""]
    edges: Float[Array, "5"]
    load_laws: PowerLaw
    interference_law: PowerLaw
    interaction: str = eqx.field(static=True)
    quadrature_nodes: int = eqx.field(static=True)
    quadrature: str = eqx.field(static=True, default="gauss-legendre")
    quadrature_tolerance: float = eqx.field(static=True, default=1e-10)

    @classmethod
    def from_dimensionless(cls, s: DimensionlessScene, interaction: str, quadrature_nodes: int,
                           quadrature: str = "gauss-legendre", quadrature_tolerance: float = 1e-10):
        return cls(
            D=s.D,
            log_a_min=s.log_a_min,
            log_density=s.log_density,
            edges=regime_edges(s.log_a_c),
            load_laws=regime_load_laws(s.D, s.log_G, s.log_hardness, s.kappa, s.log_a_c),
            interference_law=interference(s.D, s.log_G),
            interaction=interaction,
            quadrature_nodes=quadrature_nodes,
            quadrature=quadrature,
            quadrature_tolerance=quadrature_tolerance,
        )

    def intervals(self, log_a_l):
        """Each regime's range of `ln a`, clipped to `(ln a_min, ln a_l]`; empty ones have length 0."""
        lower = jnp.clip(self.edges[:-1], self.log_a_min, log_a_l)
        upper = jnp.clip(self.edges[1:], self.log_a_min, log_a_l)
        return lower, upper

    def distribution(self, log_a_l) -> PowerLaw:
        return size_distribution(self.D, log_a_l, self.log_density)

    def regime_load(self, log_a_l):
        """Eqs. (31)–(34): `∫ f(a) n(a) da` over each regime, in closed form."""
        lower, upper = self.intervals(log_a_l)
        return (self.load_laws * self.distribution(log_a_l)).integral(lower, upper)

    def regime_stiffness(self, log_a_l, log_load):
        """Eqs. (36)–(38): `∫ k(a) n(a) da` over each regime, and the breakdown flag."""
        lower, upper = self.intervals(log_a_l)
        has_stiffness = jnp.asarray(_HAS_STIFFNESS, lower.dtype)
        integrand = stiffness_without_interaction(self.load_laws, self.interference_law) * self.distribution(log_a_l)
        closed_form = integrand.integral(lower, upper) * has_stiffness
        sign = INTERACTION_SIGNS[self.interaction]
        if sign == 0.0:
            return closed_form, jnp.array(False)
        ratio = interaction_ratio(self.load_laws, self.interference_law, log_load)
        nonempty = (upper > lower) & (has_stiffness > 0)
        if sign < 0:
            breakdown = jnp.any(nonempty & (breakdown_log_area(ratio) <= upper))
        else:
            breakdown = jnp.array(False)
        # At a breakdown point the value is discarded; a zero ratio keeps its gradient finite
        # so that one bad point cannot poison the gradient of a batch.
        ratio = PowerLaw(jnp.where(breakdown, -jnp.inf, ratio.log_coeff), ratio.exponent)

        def correction(t, density_log_coeff, density_exponent, ratio_log_coeff, ratio_exponent):
            # k₀ n a (1/(1 ± r) - 1), with respect to t = ln a
            sr = sign * jnp.exp(ratio_log_coeff + ratio_exponent * t)
            return jnp.exp(density_log_coeff + (density_exponent + 1.0) * t) * (-sr / (1.0 + sr))

        rows = (integrand.log_coeff, integrand.exponent, ratio.log_coeff, ratio.exponent)
        interaction_part = integrate_rows(correction, rows, lower, upper, method=self.quadrature,
                                          nodes=self.quadrature_nodes, tolerance=self.quadrature_tolerance)
        return closed_form + interaction_part * has_stiffness, breakdown

    def real_area(self, log_a_l):
        """`A_r* = ∫ a n(a) da` over `(a_min, a_l]`, all regimes."""
        area_law = self.distribution(log_a_l) * PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D))
        return area_law.integral(self.log_a_min, jnp.maximum(log_a_l, self.log_a_min))

    def response(self, log_a_l, log_load):
        stiffness, breakdown = self.regime_stiffness(log_a_l, log_load)
        return JointResponse(self.regime_load(log_a_l), stiffness, self.real_area(log_a_l), breakdown)
