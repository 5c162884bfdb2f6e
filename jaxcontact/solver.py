"""A safeguarded Newton root-finder for monotone scalar functions, as an optimistix solver.

optimistix offers bisection (robust, linear) and Newton (fast, unbracketed: its `lower`/`upper`
options only clip). The a_l solve wants both: the residual `ln F_t(a_l) - ln F` is increasing
and nearly linear in `ln a_l`, but has kinks at the regime boundaries and is `-∞` at `a_min`. This
is the classic `rtsafe`: a Newton step when it lands inside the current bracket, bisection
otherwise. It runs inside `optimistix.root_find`; `solve_increasing` differentiates the root by
the implicit function theorem (a `custom_jvp`), never by unrolling. (optimistix's own
`ImplicitAdjoint` raises on a non-finite Jacobian, which would let one bad point of a batch
abort the whole gradient.)
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
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

    Differentiable in `args` by the implicit function theorem, `dy = -(∂fn/∂args · dargs) / (∂fn/∂y)`
    (a `custom_jvp`, so reverse mode works by transposition). Never raises: a solve that runs
    out of steps comes back with `converged = False`, and a non-finite or non-positive slope at
    the root (a point the caller will flag) gives a zero tangent instead of an error, so one
    bad point cannot abort the gradient of a batch.
    """
    return _root(fn, tolerance, max_steps, y0, lower, upper, args)


@functools.partial(jax.custom_jvp, nondiff_argnums=(0, 1, 2))
def _root(fn, tolerance, max_steps, y0, lower, upper, args):
    solver = BracketedNewton(rtol=tolerance, atol=tolerance)
    sol = optx.root_find(fn, solver, y0, args, options=dict(lower=lower, upper=upper),
                         max_steps=max_steps, throw=False)
    return sol.value, sol.result == optx.RESULTS.successful


@_root.defjvp
def _root_jvp(fn, tolerance, max_steps, primals, tangents):
    y0, lower, upper, args = primals
    args_dot = tangents[3]
    y, converged = _root(fn, tolerance, max_steps, y0, lower, upper, args)
    _, slope = jax.jvp(lambda x: fn(x, args), (y,), (jnp.ones_like(y),))
    _, f_dot = jax.jvp(lambda a: fn(y, a), (args,), (args_dot,))
    good = jnp.isfinite(slope) & (slope > 0)
    y_dot = jnp.where(good, -f_dot / jnp.where(good, slope, 1.0), 0.0)
    return (y, converged), (y_dot, np.zeros(jnp.shape(converged), dtype=jax.dtypes.float0))
