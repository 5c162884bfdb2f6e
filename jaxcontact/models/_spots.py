"""The spots of a largest-spot joint at a solved state, one by one: what partial slip needs.

The closed-form totals of a joint (`AbstractJoint.response`) integrate each spot's load and
stiffness over the size distribution; a spot's Cattaneo–Mindlin law (`physics._mindlin`) is not a
power law of its area, so the tangential cycle integrates it spot by spot. `SpotFamilies` are
those spots: families of power laws in the contact area over ranges of `t = ln a*`.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import PowerLaw
from ..physics import AbstractInteraction, NoInteraction

# A family's `r` where the model has no interaction: e^-200, and `NoInteraction` ignores it anyway.
_NO_RATIO = -200.0


class SpotFamilies(eqx.Module):
    """The spots of a joint at one state, one family per regime (dimensionless: areas in `A_a`,
    loads in `E A_a`, stiffnesses in `E √A_a`).

    **Fields:** `count`, `dN/dt = n(a) a`, spots per unit of `t = ln a*`; `load`, one spot's load
    f*(a); `stiffness`, one spot's initial unloading stiffness without interaction k₀*(a);
    `ratio`, `r(a) = σ'/ξ'` at the load (Eq. 22), which the `interaction` turns into the factor
    `k/k₀`; `lower`, `upper`, each family's range of `t`.
    """

    count: PowerLaw
    load: PowerLaw
    stiffness: PowerLaw
    ratio: PowerLaw
    interaction: AbstractInteraction
    lower: Float[Array, " families"]
    upper: Float[Array, " families"]

    @classmethod
    def without_interaction(cls, count: PowerLaw, load: PowerLaw, stiffness: PowerLaw, lower, upper) -> SpotFamilies:
        """Families whose spots do not interact (JZZ, toy models)."""
        ratio = PowerLaw(jnp.full_like(lower, _NO_RATIO), jnp.zeros_like(lower))
        return cls(count, load, stiffness, ratio, NoInteraction(), lower, upper)

    def unloading_stiffness(self, t):
        """One spot's initial unloading stiffness `k₀(a)·factor(r(a))` at `t = ln a*` (shape: the
        families' axis leading `t`'s trailing ones)."""
        return self.stiffness.expanded()(t) * self.interaction.spot_factor(self.ratio.expanded()(t))

    def at(self, t):
        """`(count, load, unloading stiffness)` of the spots at `t`, shaped as `t` (families leading)."""
        return self.count.expanded()(t), self.load.expanded()(t), self.unloading_stiffness(t)
