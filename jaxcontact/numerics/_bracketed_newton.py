"""`BracketedNewton`: Newton's method safeguarded by a bracket, as an optimistix root finder
(the classic `rtsafe`), for the loop of `rootfind.solve_increasing`."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

import equinox as eqx
import jax.numpy as jnp
import optimistix as optx
from jaxtyping import PyTree, Scalar


class _BracketState(eqx.Module):
    lower: Scalar
    upper: Scalar
    step: Scalar
    residual: Scalar
    pending: Scalar  # `step` is the next step, not yet taken (true only for the state from `init`)


def _safeguarded_newton(fn, slope_fn, y, args, lower, upper):
    """One `rtsafe` step from `y` in `[lower, upper]`: `(new_y, state, aux)`; the state keeps the residual."""
    residual, aux = fn(y, args)
    slope = slope_fn(y, args)
    below = residual < 0
    lower = jnp.where(below, y, lower)
    upper = jnp.where(below, upper, y)
    newton = y - residual / slope
    # Inclusive: at an exact root the Newton point *is* the new bracket end.
    inside = jnp.isfinite(newton) & (newton >= lower) & (newton <= upper)
    new_y = jnp.where(inside, newton, 0.5 * (lower + upper))
    return new_y, _BracketState(lower, upper, new_y - y, residual, jnp.array(False)), aux


class BracketedNewton(optx.AbstractRootFinder):
    """Newton's method safeguarded by a bracket, for increasing `R → R` functions.

    Requires `options=dict(lower=..., upper=...)` with `fn(lower) ≤ 0 ≤ fn(upper)`, or
    `options=dict(state=...)`, the state of a step already taken that ended at `y0` (so that
    steps taken before the loop are not repeated). Terminates once a step (or the bracket) is
    smaller than `atol + rtol·|y|`, checked at the initial point too: a point that starts at a
    root costs at most one evaluation and no iteration.
    """

    rtol: float
    atol: float
    slope: Callable  # `(y, args) ↦ ∂fn/∂y`
    norm: ClassVar[Callable[[PyTree], Scalar]] = jnp.abs

    def init(self, fn, y, args, options: dict[str, Any], f_struct, aux_struct, tags):
        del aux_struct, tags
        if "state" in options:  # the state of the step that led to `y`, taken before the loop
            return options["state"]
        # Evaluate at the initial point, so that a point that already is a root (to tolerance)
        # terminates before the first iteration.
        lower = jnp.asarray(options["lower"], f_struct.dtype)
        upper = jnp.asarray(options["upper"], f_struct.dtype)
        _, state, _ = _safeguarded_newton(fn, self.slope, y, args, lower, upper)
        return eqx.tree_at(lambda st: st.pending, state, jnp.array(True))

    def step(self, fn, y, args, options, state: _BracketState, tags):
        del options, tags
        return _safeguarded_newton(fn, self.slope, y, args, state.lower, state.upper)

    def terminate(self, fn, y, args, options, state: _BracketState, tags):
        del fn, args, options, tags
        scale = self.atol + self.rtol * jnp.abs(y)
        done = (jnp.abs(state.step) < scale) | (state.upper - state.lower < scale) | (state.residual == 0)
        return done, optx.RESULTS.successful

    def postprocess(self, fn, y, aux, args, options, state, tags, result):
        # Stopped by the check in `init`: take the (tolerance-sized) step it found, so that the
        # root is as accurate as after a step in the loop.
        return jnp.where(state.pending, y + state.step, y), aux, {}
