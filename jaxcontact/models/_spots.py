"""The spots of a joint at a solved state, one by one: what partial slip needs.

The closed-form totals of a model integrate each spot's load and stiffness over the spots; a spot's
Cattaneo–Mindlin law (`physics._mindlin`) is not a power law of its size, so the tangential cycle
integrates it spot by spot. `SpotFamilies` are those spots: families over ranges of the log of a
size variable (the contact area of a largest-spot joint, the interference of a GW summit).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

from ..numerics import PowerLaw
from ..physics import AbstractInteraction, NoInteraction

# A family's `r` where the model has no interaction: e^-200, and `NoInteraction` ignores it anyway.
_NO_RATIO = -200.0


class SummitCount(eqx.Module):
    """`dN/dt` of Greenwood–Williamson summits over a flat at separation `d`, in `t = ln w` (w = z − d,
    the interference): `N φ(d + w) w`, φ linear on each family's interval of the height table
    (`phi0 + slope (z − z0)`), N the summits in the nominal area."""

    log_count: Float[Array, ""]
    separation: Float[Array, ""]
    # One row per family; `expanded()` adds a trailing axis to evaluate each on its own nodes.
    phi0: Float[Array, "families *node"]
    slope: Float[Array, "families *node"]
    z0: Float[Array, "families *node"]

    def expanded(self) -> SummitCount:
        return SummitCount(self.log_count, self.separation, self.phi0[:, None], self.slope[:, None], self.z0[:, None])

    def __call__(self, t):
        w = jnp.exp(t)
        return jnp.exp(self.log_count) * (self.phi0 + self.slope * (self.separation + w - self.z0)) * w


class GaussianSummitCount(eqx.Module):
    """`dN/dt` of Greenwood–Williamson summits of standard normal heights (in units of their
    deviation σ_s) over a flat at separation h, in `t = ln ŵ` (ŵ = s − h): `N φ(h + ŵ) ŵ`."""

    log_count: Float[Array, ""]
    separation: Float[Array, ""]

    def expanded(self) -> GaussianSummitCount:
        return self

    def __call__(self, t):
        w = jnp.exp(t)
        s = self.separation + w
        return jnp.exp(self.log_count - 0.5 * s * s - 0.5 * math.log(2.0 * math.pi)) * w


class Separated(eqx.Module):
    """A Greenwood–Williamson-type model's state at one load: the flat's separation, the totals
    there (dimensionless) and the point's status."""

    separation: Float[Array, ""]
    load: Float[Array, ""]
    stiffness: Float[Array, ""]
    area: Float[Array, ""]
    status: Int[Array, ""]


class SpotFamilies(eqx.Module):
    """The spots of a joint at one state, in families over ranges of `t`, the log of a size variable:
    the contact area a* for the largest-spot models (one family per regime), the interference w*
    for Greenwood–Williamson summits (one per interval of the height table). Dimensionless: areas
    in `A_a`, lengths in `√A_a`, loads in `E A_a`, stiffnesses in `E √A_a`.

    **Fields:** `count`, `dN/dt`, spots per unit of t (`n(a) a`, a `PowerLaw`; or a `SummitCount`,
    `GaussianSummitCount`);
    `load`, one spot's load f*; `stiffness`, one spot's initial unloading stiffness without
    interaction k₀*;
    `ratio`, `r(a) = σ'/ξ'` at the load (Eq. 22), which the `interaction` turns into the factor
    `k/k₀`; `lower`, `upper`, each family's range of `t`.
    """

    count: PowerLaw | SummitCount | GaussianSummitCount
    load: PowerLaw
    stiffness: PowerLaw
    ratio: PowerLaw
    interaction: AbstractInteraction
    lower: Float[Array, " families"]
    upper: Float[Array, " families"]

    @classmethod
    def without_interaction(
        cls, count: PowerLaw | SummitCount | GaussianSummitCount, load: PowerLaw, stiffness: PowerLaw, lower, upper
    ) -> SpotFamilies:
        """Families whose spots do not interact (JZZ, toy models)."""
        ratio = PowerLaw(jnp.full_like(lower, _NO_RATIO), jnp.zeros_like(lower))
        return cls(count, load, stiffness, ratio, NoInteraction(), lower, upper)

    def unloading_stiffness(self, t):
        """One spot's initial unloading stiffness `k₀·factor(r)` at t (shape: the families' axis
        leading t's trailing ones)."""
        return self.stiffness.expanded()(t) * self.interaction.spot_factor(self.ratio.expanded()(t))

    def at(self, t):
        """`(count, load, unloading stiffness)` of the spots at `t`, shaped as `t` (families leading)."""
        return self.count.expanded()(t), self.load.expanded()(t), self.unloading_stiffness(t)


class SpotState(eqx.Module):
    """A model's state at one load with its spots (`AbstractContactModel.spot_solver`): the point's
    `status`, the `spots`, their summed initial unloading stiffness `unloading` (in `E √A_a`), and
    whether the model breaks down on unloading there (`breakdown`)."""

    status: Int[Array, ""]
    spots: SpotFamilies
    unloading: Float[Array, ""]
    breakdown: Bool[Array, ""]
