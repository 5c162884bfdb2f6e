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
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from ._elementwise import unrolled_sum
from .asperity import interference, regime_edges, regime_load_laws
from .dimensionless import DimensionlessScene
from .distribution import size_distribution
from .interaction import INTERACTION_SIGNS, breakdown_log_area, interaction_ratio, stiffness_without_interaction
from .load_pieces import AbstractLoadPieces, GenericLoadPieces, PowerLawLoadPieces
from .pole_integral import PoleIntegral
from .powerlaw import PowerLaw, exponential_integral
from .quadrature import integrate_rows

# Fully plastic asperities carry load but add no stiffness (Sec. 4.2). Plain Python values,
# not jnp arrays: a module-level array would freeze the precision that was active at import.
_HAS_STIFFNESS = (1.0, 1.0, 1.0, 0.0)
_GEOMETRIC_TERMS = 4  # powers of r taken in closed form before the remainder (see regime_stiffness)


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
        return unrolled_sum(self.regime_load(log_a_l))

    @abc.abstractmethod
    def kinks(self) -> Float[Array, "kinks"]:
        """`ln a_l*` where the slope of `F_t` jumps (a regime boundary), increasing."""

    def knots(self) -> Float[Array, "kinks_plus_2"]:
        """Ends of the smooth pieces of `F_t` in `ln a_l*`: `ln a_min*`, the kinks (clipped), 0."""
        return jnp.concatenate([self.log_a_min[None], jnp.clip(self.kinks(), self.log_a_min, 0.0),
                                jnp.zeros_like(self.log_a_min)[None]])

    def load_pieces(self) -> AbstractLoadPieces:
        """`F_t` piece by piece between its kinks, for the load-controlled solve."""
        knots = self.knots()
        return GenericLoadPieces(knots, jnp.log(jax.vmap(self.total_load)(knots)), self)

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
    quadrature: str = eqx.field(static=True, default="power-series")
    quadrature_tolerance: float = eqx.field(static=True, default=1e-10)

    @classmethod
    def from_dimensionless(cls, s: DimensionlessScene, interaction: str, quadrature_nodes: int,
                           quadrature: str = "power-series", quadrature_tolerance: float = 1e-10):
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

        Without interaction: closed forms. With interaction `k = k₀/(1 ± r)`, `k₀ = f'/ξ'`, and the
        interaction part `∫ k₀ n (1/(1 ± r) - 1) da` is integrated as follows.

        - "series" (`-r/(1+r)`, bounded, no real pole): Gauss–Legendre in `t = ln a`.
        - "paper" (`r/(1-r)`, a pole where r = 1, i.e. at breakdown): near breakdown the pole sits
          at the end of the interval and no quadrature in `t` converges. So
          `r/(1-r) = Σ_{j=1..k} r^j + r^(k+1)/(1-r)`: the powers of r are power laws (closed
          forms), and with `u = r(a)` the remainder is `C ∫ u^p/(1-u) du`, `p = δ/e + k ≥ 2` in
          every regime for k = 4. With `quadrature = "power-series"` (the default) its
          antiderivative is summed to round-off (`pole_integral`); otherwise it is integrated by
          quadrature in `w = -ln(1-u)` (`_remainder_by_quadrature`).
        """
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
        # At a breakdown point the value is discarded; a tiny ratio keeps every number (and
        # gradient) finite, so that one bad point cannot poison the gradient of a batch.
        ratio = PowerLaw(jnp.where(breakdown, -200.0, ratio.log_coeff), ratio.exponent)
        # Plastic spots have no stiffness: only the first three regimes are integrated.
        rows = slice(0, 3)
        density = PowerLaw(integrand.log_coeff[rows], integrand.exponent[rows] + 1.0)  # k₀ n a, in t = ln a
        ratio, lo, hi = ratio[rows], lower[rows], upper[rows]
        options = dict(method=self.quadrature, nodes=self.quadrature_nodes, tolerance=self.quadrature_tolerance)
        if sign > 0:
            def series_correction(t, d_log, d_rate, r_log, r_rate):
                r = jnp.exp(r_log + r_rate * t)
                return jnp.exp(d_log + d_rate * t) * (-r / (1.0 + r))

            part = integrate_rows(series_correction, (density.log_coeff, density.exponent, ratio.log_coeff,
                                                      ratio.exponent), lo, hi, **options)
            return closed_form + jnp.concatenate([part, jnp.zeros_like(part[:1])]), breakdown
        corrections = _paper_correction(density, ratio, lo, hi, self.quadrature, options)
        # Stacked last, so that each regime stays its own elementwise chain (see `_paper_correction`).
        return jnp.stack([closed_form[i] + c for i, c in enumerate(corrections)] + [closed_form[3]]), breakdown

    def real_area(self, log_a_l):
        """`A_r* = ∫ a n(a) da` over `(a_min, a_l]`, all regimes."""
        area_law = self.distribution(log_a_l) * PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D))
        return area_law.integral(self.log_a_min, jnp.maximum(log_a_l, self.log_a_min))

    def response(self, log_a_l, log_load):
        stiffness, breakdown = self.regime_stiffness(log_a_l, log_load)
        return JointResponse(self.regime_load(log_a_l), stiffness, self.real_area(log_a_l), breakdown)


def _paper_correction(density: PowerLaw, ratio: PowerLaw, lower, upper, quadrature: str,
                      options: dict) -> list[Float[Array, ""]]:
    """`∫ k₀ n r/(1-r) da` over each regime with stiffness (interaction "paper", `regime_stiffness`).

    `density` and `ratio` are `k₀ n a` and `r` as laws in `t = ln a`, one row per regime. With
    `u = r(a)`, `r/(1-r) = Σ_{j=1..k} u^j + u^(k+1)/(1-u)`: the powers are closed forms, and the
    remainder is `C ∫ u^p/(1-u) du` with `C = e^(d - δr/q) / q` and `p = δ/q + k` (`d, δ`: the
    density's log-coefficient and rate; `r, q`: the ratio's).

    **Returns:** one correction per regime, as a list. Each regime is computed as its own chain
    of scalar operations: under `vmap` a vector of regimes would become a short minor axis, and
    XLA on CPU does not vectorise a loop whose lanes read different coefficients (the pole
    series' 21 Horner steps). Row by row, a whole 200-load `Solution` takes 0.75–0.8x the time
    and 1e5 loads 0.35x, for a longer compile (forward 1.3x, gradient about 2x).
    """
    series = quadrature == "power-series"
    poles = PoleIntegral.build(density.exponent / ratio.exponent + _GEOMETRIC_TERMS) if series else None
    corrections = []
    for i in range(lower.shape[0]):
        d, r, lo, hi = density[i], ratio[i], lower[i], upper[i]
        powers = sum(exponential_integral(d.log_coeff + j * r.log_coeff, d.exponent + j * r.exponent, lo, hi)
                     for j in range(1, _GEOMETRIC_TERMS + 1))
        if not series:
            corrections.append(powers + _remainder_by_quadrature(d, r, lo, hi, options))
            continue
        pole, log_coeff = poles[i], d.log_coeff - d.exponent * r.log_coeff / r.exponent
        remainder = pole(r.log_coeff + r.exponent * hi, log_coeff) - pole(r.log_coeff + r.exponent * lo, log_coeff)
        # The integrand is positive: a difference below 0 is round-off between two nearly equal
        # ends, and an empty interval is exactly 0 (its ends may even lie past the pole, where
        # a_min itself is beyond breakdown). Dividing by q last (not `- ln q` in the exponent)
        # ends the sum in a division, which XLA computes once and shares instead of copying the
        # polynomial work into every output that uses the stiffness (1.3x for a whole Solution).
        corrections.append(powers + jnp.where(hi > lo, jnp.maximum(remainder, 0.0), 0.0) / r.exponent)
    return corrections


def _remainder_by_quadrature(density: PowerLaw, ratio: PowerLaw, lower, upper, options: dict):
    """The remainder `C ∫ u^p/(1-u) du` of `_paper_correction` by quadrature.

    In `w = -ln(1-u)` it is `∫ C u^p dw`: bounded and smooth, over an interval that grows only
    like `-ln(1 - r_max)` as the pole approaches. `pole_integral` does the same integral exactly;
    this is its cross-check and the accuracy study's quadrature knob.
    """
    d_log, d_rate, r_log, r_rate = density.log_coeff, density.exponent, ratio.log_coeff, ratio.exponent
    # u < 1 inside every interval the caller keeps; an empty one may lie past the pole (a_min
    # beyond breakdown), and is clamped there so that its zero length still gives exactly 0.
    below_pole = -float(jnp.finfo(lower.dtype).eps)
    w_lo = -jnp.log1p(-jnp.exp(jnp.minimum(r_log + r_rate * lower, below_pole)))
    w_hi = -jnp.log1p(-jnp.exp(jnp.minimum(r_log + r_rate * upper, below_pole)))
    log_coeff = d_log - d_rate * r_log / r_rate - jnp.log(r_rate)
    power = d_rate / r_rate + _GEOMETRIC_TERMS
    tiny = float(jnp.finfo(lower.dtype).tiny)

    def remainder(w, log_coeff, power):
        # u^power with u = 1 - e^(-w). u = 0 only on an empty interval (w = 0), where the floor
        # gives tiny^power = 0 without a branch (power ≥ 2): a `where` here would stop XLA from
        # vectorising the loop.
        u = jnp.maximum(-jnp.expm1(-w), tiny)
        return jnp.exp(log_coeff + power * jnp.log(u))

    return integrate_rows(remainder, (log_coeff, power), w_lo, w_hi, **options)
