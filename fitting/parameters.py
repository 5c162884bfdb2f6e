"""Fittable parameters: where each lives in a `Scene`, its bounds, and its coordinates.

Each parameter has a *statistical* coordinate in which the Gauss–Newton covariance is formed
(linear for D and ν, logarithmic for the positive scales G, E, H, l_min, area: a relative
uncertainty is what a 5 % noise level produces), and an unconstrained *optimiser* coordinate
`u` with `s = low + (high - low) · sigmoid(u)`, so that no step can leave the bounds.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp

import jaxcontact as jc
from jaxcontact import InputError


@dataclasses.dataclass(frozen=True)
class FitParameter:
    """A parameter as the fit sees it: the scene's `ParameterSpec`, searched over `low`..`high`."""

    name: str
    get: Callable[[jc.Scene], object]
    low: float  # bounds of the physical value
    high: float
    log: bool  # statistical coordinate is ln(value)
    unit: str

    @classmethod
    def of(cls, spec: jc.ParameterSpec) -> FitParameter:
        """The fit's view of a scene parameter: its default search range, log coordinate for scales."""
        return cls(spec.name, spec.get, *spec.search, spec.log, spec.unit)

    @property
    def stat_bounds(self) -> tuple[float, float]:
        return (math.log(self.low), math.log(self.high)) if self.log else (self.low, self.high)

    def to_stat(self, value):
        return jnp.log(value) if self.log else value

    def from_stat(self, s):
        return jnp.exp(s) if self.log else s

    def stat_from_u(self, u):
        lo, hi = self.stat_bounds
        # Clamped: a saturated sigmoid must not land exactly on an open bound (D = 2, ν = 0.5).
        fraction = jnp.clip(jax.nn.sigmoid(u), 1e-9, 1.0 - 1e-9)
        return lo + (hi - lo) * fraction

    def u_from_stat(self, s):
        lo, hi = self.stat_bounds
        p = (s - lo) / (hi - lo)
        return jnp.log(p) - jnp.log1p(-p)


PARAMETERS = {name: FitParameter.of(spec) for name, spec in jc.PARAMETERS.items()}


def resolve(names) -> tuple[FitParameter, ...]:
    """The `FitParameter`s for `names` (a sequence or a comma-separated string)."""
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    names = list(names)
    if not names:
        raise InputError("params must name at least one parameter")
    unknown = [n for n in names if n not in PARAMETERS]
    if unknown:
        raise InputError(f"params: {', '.join(map(repr, unknown))} cannot be fitted (allowed: {', '.join(PARAMETERS)})")
    if len(set(names)) != len(names):
        raise InputError(f"params = {names} names a parameter twice")
    return tuple(PARAMETERS[n] for n in names)


def with_stat(scene: jc.Scene, params, stat) -> jc.Scene:
    """The scene with the fitted parameters set from their statistical coordinates."""
    for i, p in enumerate(params):
        scene = eqx.tree_at(p.get, scene, p.from_stat(stat[i]))
    return scene
