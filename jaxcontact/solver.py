"""A safeguarded Newton root-finder for monotone scalar functions, as an optimistix solver.

optimistix offers bisection (robust, linear) and Newton (fast, unbracketed: its `lower`/`upper`
options only clip). The a_l solve wants both: the residual `ln F_t(a_l) - ln F` is increasing
and nearly linear in `ln a_l`, but has kinks at the regime boundaries and is `-∞` at `a_min`. This
is the classic `rtsafe`: a Newton step when it lands inside the current bracket, bisection
otherwise. Plugged into `optimistix.root_find`, it is differentiated by the implicit function
theorem (`ImplicitAdjoint`), never by unrolling.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import optimistix as optx
from jaxtyping import Array, PyTree, Scalar


class _BracketState(eqx.Module):
    lower: Scalar
    upper: Scalar
    step: Scalar
    residual: Scalar


class BracketedNewton(optx.AbstractRootFinder):
    """Newton's method safeguarded by a bracket, for increasing `R → R` functions.

    Requires `options=dict(lower=..., upper=...)` with `fn(lower) ≤ 0 ≤ fn(upper)`.
    Terminates once a step (or the bracket) is smaller than `atol + rtol·|y|`.
    """

    rtol: float
    atol: float
    norm: ClassVar[Callable[[PyTree], Scalar]] = jnp.abs

    def init(self, fn, y, args, options: dict[str, Any], f_struct, aux_struct, tags):
        del fn, args, aux_struct, tags
        inf = jnp.array(jnp.inf, f_struct.dtype)
        return _BracketState(lower=jnp.asarray(options["lower"], f_struct.dtype),
                             upper=jnp.asarray(options["upper"], f_struct.dtype), step=inf, residual=inf)

    def step(self, fn, y, args, options, state: _BracketState, tags):
        del options, tags
        (residual, aux), (slope, _) = jax.jvp(lambda x: fn(x, args), (y,), (jnp.ones_like(y),))
        below = residual < 0
        lower = jnp.where(below, y, state.lower)
        upper = jnp.where(below, state.upper, y)
        newton = y - residual / slope
        # Inclusive: at an exact root the Newton point *is* the new bracket end.
        inside = jnp.isfinite(newton) & (newton >= lower) & (newton <= upper)
        new_y = jnp.where(inside, newton, 0.5 * (lower + upper))
        return new_y, _BracketState(lower, upper, new_y - y, residual), aux

    def terminate(self, fn, y, args, options, state: _BracketState, tags):
        del fn, args, options, tags
        scale = self.atol + self.rtol * jnp.abs(y)
        done = (jnp.abs(state.step) < scale) | (state.upper - state.lower < scale) | (state.residual == 0)
        return done, optx.RESULTS.successful

    def postprocess(self, fn, y, aux, args, options, state, tags, result):
        return y, aux, {}


def solve_increasing(fn, y0, args, lower, upper, *, tolerance: float, max_steps: int):
    """Root of an increasing `fn(y, args)` in `[lower, upper]`; returns `(y, converged)`.

    Differentiable in `args` by the implicit function theorem. Never raises: a solve that
    runs out of steps comes back with `converged = False`.
    """
    solver = BracketedNewton(rtol=tolerance, atol=tolerance)
    sol = optx.root_find(fn, solver, y0, args, options=dict(lower=lower, upper=upper),
                         max_steps=max_steps, throw=False, adjoint=optx.ImplicitAdjoint())
    return sol.value, sol.result == optx.RESULTS.successful
