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
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError

# An optimum within the first share of a parameter's search range from one of its ends, or within the
# second with a Gauss–Newton step that leaves the range there, is on the bound: not a success.
ON_BOUND = (1e-3, 1e-2)


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

    # Host numbers stay on the host (numpy): an eager JAX operation compiles on its first use.
    def to_stat(self, value):
        return _numpy_or_jax(value).log(value) if self.log else value

    def from_stat(self, s):
        return _numpy_or_jax(s).exp(s) if self.log else s

    def stat_and_slope_from_u(self, u: float) -> tuple[float, float]:
        """The statistical coordinate at optimiser coordinate `u`, and `d stat / d u`."""
        lo, hi = self.stat_bounds
        sigmoid = 0.5 * (1.0 + math.tanh(0.5 * float(u)))  # no overflow for any u
        # Clamped: a saturated sigmoid must not land exactly on an open bound (D = 2, ν = 0.5).
        fraction = min(max(sigmoid, 1e-9), 1.0 - 1e-9)
        slope = (hi - lo) * sigmoid * (1.0 - sigmoid) if fraction == sigmoid else 0.0
        return lo + (hi - lo) * fraction, slope

    def stat_from_u(self, u: float) -> float:
        return self.stat_and_slope_from_u(u)[0]

    def bound_reached(self, s: float, step: float) -> str | None:
        """A warning when the statistical coordinate `s` sits on a search bound, else None: within
        `ON_BOUND[0]` of the range from one end, or within `ON_BOUND[1]` with the Gauss–Newton step
        `step` from there leaving the range through it (the optimiser's coordinate flattens at the
        bound, so that it stops short of an optimum beyond). The interval and the fit's success mean
        nothing there."""
        lo, hi = self.stat_bounds
        tight, margin = (share * (hi - lo) for share in ON_BOUND)
        if s - lo < tight or (s - lo < margin and s + step <= lo):
            side, bound = "lower", self.low
        elif hi - s < tight or (hi - s < margin and s + step >= hi):
            side, bound = "upper", self.high
        else:
            return None
        value = float(self.from_stat(s))
        return f"{self.name} = {value:.4g} is on its {side} search bound {bound:g}: the optimum lies at or beyond it"

    def u_from_stat(self, s):
        lo, hi = self.stat_bounds
        p = (s - lo) / (hi - lo)
        return _numpy_or_jax(p).log(p) - _numpy_or_jax(p).log1p(-p)


def _numpy_or_jax(x):
    return jnp if isinstance(x, jax.Array) else np


PARAMETERS = {name: FitParameter.of(spec) for name, spec in jc.PARAMETERS.items()}


def resolve(names) -> tuple[FitParameter, ...]:
    """The `FitParameter`s for `names` (a sequence or a comma-separated string)."""
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    if not isinstance(names, (list, tuple)) or not all(isinstance(n, str) for n in names):
        # A method passed where the parameters go (`fit(loads, K, scene, LevenbergMarquardt())`) lands here.
        raise InputError(
            f"params = {names!r} must be parameter names, e.g. ('D', 'G') (allowed: {', '.join(PARAMETERS)}); "
            "the optimiser goes in method="
        )
    names = list(names)
    if not names:
        raise InputError("params must name at least one parameter")
    unknown = [n for n in names if n not in PARAMETERS]
    if unknown:
        raise InputError(f"params: {', '.join(map(repr, unknown))} cannot be fitted (allowed: {', '.join(PARAMETERS)})")
    if len(set(names)) != len(names):
        raise InputError(f"params = {names} names a parameter twice")
    return tuple(PARAMETERS[n] for n in names)


def stat_of_u(params, u):
    """The statistical coordinates at optimiser coordinates `u`, as a JAX function (for programs that
    optimise or sample inside `jit`; `FitParameter.stat_from_u` is the host's, clamped, twin)."""
    low = jnp.array([p.stat_bounds[0] for p in params])
    span = jnp.array([p.stat_bounds[1] - p.stat_bounds[0] for p in params])
    return low + span * jax.nn.sigmoid(u)


def with_stat(scene: jc.Scene, params, stat) -> jc.Scene:
    """The scene with the fitted parameters set from their statistical coordinates."""
    for i, p in enumerate(params):
        scene = eqx.tree_at(p.get, scene, p.from_stat(stat[i]))
    return scene
