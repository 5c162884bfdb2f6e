"""The totals of Greenwood–Williamson summits with a tabulated height PDF (`MeasuredAsperities`), in
closed form.

With a rigid flat at height d, a summit at height z has the interference ω = z − d, and carries
`P(ω)` on the contact area `A(ω)` of its summit law, a power law `c ω^β` in each band
`[ω_k, ω_(k+1))` (`physics.SummitBands`). Summed over the summits (density η per unit area, heights
φ linear between the table's points), each band's total is `η c J_β^k(d)`, with

    J_n^k(d) = ∫ (z − d)^n φ(z) dz over the z where z − d ∈ [ω_k, ω_(k+1)),

a sum of closed forms, one per interval of the table (`band_integral`). The loading stiffness is
`K = −dF/dd` exactly: each band's `η c β J_(β−1)^k`, and, where the law's load jumps by ΔP at an
edge ω_k (the Kogut–Etsion fits are not continuous), `η ΔP φ(d + ω_k)` of the summits crossing it.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..physics._summit_law import SummitBands


def _power(t, p):
    """`t^p` for `t ≥ 0`, 0 at 0 with a finite derivative (a kink of the integrand, not a NaN)."""
    positive = t > 0
    return jnp.where(positive, jnp.where(positive, t, 1.0) ** p, 0.0)


def band_integral(order, d, heights, pdf, lower=0.0, upper=jnp.inf):
    """`∫ (z − d)^n φ(z) dz` over the z of the table with `z − d` in `[lower, upper]`, φ linear between
    `(heights, pdf)`: on each interval, with `t = z − d` clipped to the band (and to the table's top),
    φ = φ(t0) + s (t − t0) and `∫ t^n (φ0 + s (t − t0)) dt = φ0 [t^(n+1)/(n+1)] + s ([t^(n+2)/(n+2)] −
    t0 [t^(n+1)/(n+1)])`. `order`, `lower` and `upper` broadcast against a trailing axis of intervals."""
    top = heights[-1] - d
    clip = lambda t: jnp.minimum(jnp.clip(t, lower, upper), top)  # noqa: E731
    t_low, t_high = clip(heights[:-1] - d), clip(heights[1:] - d)
    slope = (pdf[1:] - pdf[:-1]) / (heights[1:] - heights[:-1])
    phi_low = pdf[:-1] + slope * (d + t_low - heights[:-1])
    first = (_power(t_high, order + 1.0) - _power(t_low, order + 1.0)) / (order + 1.0)
    second = (_power(t_high, order + 2.0) - _power(t_low, order + 2.0)) / (order + 2.0)
    return jnp.sum(phi_low * first + slope * (second - t_low * first), axis=-1)


class BandTotals(eqx.Module):
    """Per band of the summit law (dimensionless, lengths in the table's span): the load, the loading
    stiffness `−dF/dd`, the initial unloading stiffness and the real area."""

    load: Float[Array, " bands"]
    stiffness: Float[Array, " bands"]
    unloading: Float[Array, " bands"]
    area: Float[Array, " bands"]


class SummitTable(eqx.Module):
    """Measured summits in the solve's units: heights `u ∈ [0, 1]` from the table's lowest point in
    units of its span (the root finder's tolerance is absolute in u), φ normalised over u, the
    summits per nominal area `exp(log_eta)`, and the summit law's `bands` with ω in units of the span.
    `span` is the table's span and `exp(log_R)` the summits' radius, in `√A_a`."""

    span: Float[Array, ""]
    heights: Float[Array, " table"]
    pdf: Float[Array, " table"]
    log_eta: Float[Array, ""]
    log_R: Float[Array, ""]
    bands: SummitBands

    def _integral(self, order, d):
        edges = self.bands.edges
        return band_integral(order[:, None], d, self.heights, self.pdf, edges[:-1, None], edges[1:, None])

    def load(self, d) -> Float[Array, " bands"]:
        """F* per band with the flat at u = d."""
        law = self.bands.load
        return jnp.exp(self.log_eta + law.log_coeff) * self._integral(law.exponent, d)

    def stiffness(self, d) -> Float[Array, " bands"]:
        """The loading stiffness `−dF*/dd*` per band (`E √A_a`), with the flat at u = d: each band's
        smooth part and the summits crossing into it (module docstring)."""
        law = self.bands.load
        smooth = law.exponent * jnp.exp(law.log_coeff) * self._integral(law.exponent - 1.0, d)
        inner = self.bands.edges[1:-1]
        finite = jnp.isfinite(inner)
        density = jnp.interp(jnp.where(finite, d + inner, 2.0), self.heights, self.pdf, left=0.0, right=0.0)
        crossing = jnp.concatenate([jnp.zeros_like(inner[:1]), self.bands.load_jumps() * density])
        return jnp.exp(self.log_eta) * (smooth + crossing) / self.span

    def totals(self, d) -> BandTotals:
        """Every total per band with the flat at u = d (module docstring); stiffnesses in `E √A_a`."""
        eta = jnp.exp(self.log_eta)
        unloading, area = self.bands.unloading_stiffness(), self.bands.area
        return BandTotals(
            load=self.load(d),
            stiffness=self.stiffness(d),
            unloading=eta * jnp.exp(unloading.log_coeff) * self._integral(unloading.exponent, d),
            area=eta * jnp.exp(area.log_coeff) * self._integral(area.exponent, d),
        )


def summit_table(heights, pdf, density, log_R, bands: SummitBands, log_length) -> SummitTable:
    """The `SummitTable` of a height table (m) and its PDF (any normalisation), `density` summits per
    m², the summits' radius `exp(log_R)` and the summit law's `bands`, both in the scene's units
    (`√A_a = exp(log_length)` m)."""
    span = (heights[-1] - heights[0]) * jnp.exp(-log_length)
    u = (heights - heights[0]) / (heights[-1] - heights[0])
    pdf = pdf / jnp.sum(0.5 * (pdf[1:] + pdf[:-1]) * jnp.diff(u))
    log_eta = jnp.log(density) + 2.0 * log_length
    return SummitTable(span, u, pdf, log_eta, log_R, bands.in_units(jnp.log(span)))


def log_load(table: SummitTable, d):
    return jnp.log(jnp.sum(table.load(d)))


# The root finder's residual and slope take every traced value as an argument (it differentiates the
# root implicitly, and a closure would hide them from it); increasing in y = −d.
def residual(y, args):
    table, target = args
    return log_load(table, -y) - target, None


def residual_slope(y, args):
    table, _ = args
    return table.span * jnp.sum(table.stiffness(-y)) / jnp.sum(table.load(-y))
