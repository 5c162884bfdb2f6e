"""What a fit can observe: each measured curve is an `AbstractObservable`, which says how its values
enter the fit (its target), how the model predicts them (its residuals) and what scale it has.

- `Stiffness()`: `r = ln K_model(F; θ) − ln K` (relative errors, as measurement noise on K usually is);
- `Approach()`: `r = δ_model(F; θ) − δ` (m), the approach relative to the preload F0
  (`jaxcontact.applications.approach_star`, piecewise Gauss–Legendre: fixed cost, cheap forward-mode
  derivatives), with a displacement sensor's absolute noise.

Data points that the model cannot evaluate at a trial θ (interaction breakdown, load out of range)
contribute a constant residual (`flagged`: `FLAGGED_RESIDUAL` in ln K; the curve's rms approach in δ)
with no gradient, so that no start can win by pushing points out of the model; points where the
model gives K = 0 (every spot plastic) contribute `ZERO_STIFFNESS_RESIDUAL`, worse than any real misfit.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.applications import approach_star

FLAGGED_RESIDUAL = 1.0  # a miss by a factor e in stiffness
# A valid point where the model says K = 0 (every spot plastic) against a measured K > 0 misses by
# an infinite factor; this stands for it, worse than any misfit a model of the data could have, so
# that no start wins by making the stiffness vanish.
ZERO_STIFFNESS_RESIDUAL = 50.0
# Gauss–Legendre nodes per piece of the approach's quadrature: ~1e-8 relative (docs/applications.md),
# far below any displacement sensor's noise.
APPROACH_NODES = 8
# The fit reads the stiffness and the status alone.
_OUTPUTS = jc.Outputs(regime_shares=False)


def rms(values) -> float:
    """The root mean square of the finite `values` (1 where there are none)."""
    values = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(values * values))) if values.size else 1.0


class AbstractObservable(eqx.Module):
    """One measured curve over the fit's loads.

    **Class attributes:** `name` (the `fit` argument it comes from, the key of `noise`, and
    `FitResult.observables`), `noise_units` (what its σ is, for messages), `misfit_unit` (what a
    relative residual of it is "in", for the misfit warning).
    """

    name: eqx.AbstractClassVar[str]
    noise_units: eqx.AbstractClassVar[str]
    misfit_unit: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def valid(self, values: np.ndarray) -> np.ndarray:
        """Where each measured value is inside its valid range (NaN, not measured, counts as valid)."""

    @abc.abstractmethod
    def target(self, values: np.ndarray) -> np.ndarray:
        """The measured `values` (NaN where not measured) as the fit's targets; `ValueError` for a
        value outside its valid range."""

    @abc.abstractmethod
    def scale(self, targets: np.ndarray) -> float:
        """The size of the targets: the unit of a relative residual, and σ when nothing else sets it."""

    @abc.abstractmethod
    def flagged(self, targets: np.ndarray) -> float:
        """The residual of a point the model cannot evaluate, before weighting."""

    @abc.abstractmethod
    def residuals(self, scene: jc.Scene, loads, target, flagged, reference_load):
        """`(r, ok, status)` at each load: the model's misfit of `target` (unweighted; `flagged` where
        the point is not valid), its valid mask and its status."""


class Stiffness(AbstractObservable):
    """The stiffness K(F) (N/m), fitted in ln K."""

    name: ClassVar[str] = "stiffness"
    noise_units: ClassVar[str] = "σ of ln K"
    misfit_unit: ClassVar[str] = "in K"

    def valid(self, values):
        return np.isnan(values) | ((values > 0) & np.isfinite(values))

    def target(self, values):
        if not np.all(self.valid(values)):
            raise InputError("stiffness must be positive and finite (valid range (0, inf)), or NaN where not measured")
        return np.log(values)

    def scale(self, targets):
        return 1.0

    def flagged(self, targets):
        return FLAGGED_RESIDUAL

    def residuals(self, scene, loads, target, flagged, reference_load):
        del reference_load
        sol = jc.solve(scene, loads, outputs=_OUTPUTS)
        ok = sol.ok & (sol.stiffness > 0)
        K = jnp.where(ok, sol.stiffness, 1.0)  # no log of NaN or 0: no NaN in any gradient
        missed = jnp.where(sol.fully_plastic, ZERO_STIFFNESS_RESIDUAL, flagged)
        return jnp.where(ok, jnp.log(K) - target, missed), ok, sol.status


class Approach(AbstractObservable):
    """The approach δ(F) − δ(F0) (m) relative to the preload F0, fitted as it is."""

    name: ClassVar[str] = "approach"
    noise_units: ClassVar[str] = "σ of the approach in m"
    misfit_unit: ClassVar[str] = "of the approach's rms"

    def valid(self, values):
        return ~np.isinf(values)

    def target(self, values):
        if not np.all(self.valid(values)):
            raise InputError("approach must be finite (m), or NaN where not measured")
        return values

    def scale(self, targets):
        return rms(targets)

    def flagged(self, targets):
        return rms(targets)

    def residuals(self, scene, loads, target, flagged, reference_load):
        scales = jc.Scales.of(scene)
        log_F = jnp.log(loads / scales.load)
        delta_star, status = approach_star(scene, log_F, jnp.log(reference_load / scales.load), APPROACH_NODES)
        ok = status == jc.Status.OK
        model = jnp.where(ok, delta_star, 0.0) * scales.length
        return jnp.where(ok, model - target, flagged), ok, status
