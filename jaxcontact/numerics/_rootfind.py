"""A safeguarded Newton root-finder for monotone scalar functions, as an optimistix solver
(`bracketed_newton.BracketedNewton`, imported when a solve is first traced).

optimistix offers bisection (robust, linear) and Newton (fast, unbracketed: its `lower`/`upper`
options only clip). The a_l solve wants both: the residual `ln F_t(a_l) - ln F` is increasing
and smooth on each piece between the regime boundaries (`AbstractJoint.load_pieces`), and `-∞`
at `a_min`. This is the classic `rtsafe`: a Newton step when it lands inside the current
bracket, bisection otherwise.

`solve_increasing` first takes a few plain Newton steps, clipped to the bracket, as straight-line
code (from a good guess they already converge), then hands the point to `optimistix.root_find`,
whose loop starts with a convergence check and so runs no iteration at all unless a point needs
more steps; its safeguarded steps are what makes the solve robust. The unrolled steps keep no
bracket on purpose: a step whose only output is the next `y` fuses with its neighbours into one
loop over the batch, while a step that also updates a bracket from the residual's sign has
three outputs that share every `exp` and `log`, and XLA (which does not duplicate such work)
cuts such a step into several loops. Steps and
the implicit derivative use the caller's closed-form slope where it has one (`slope`): the loop's
body is then smaller and compiles faster than one built on forward-mode derivatives of the
residual. The root is differentiated by the implicit function theorem (a `custom_jvp`), never by
unrolling. (optimistix's own `ImplicitAdjoint` raises on a non-finite Jacobian, which would let
one bad point of a batch abort the whole gradient.)
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._validate import InputError


def _forward_mode_slope(fn):
    def slope(y, args):
        return jax.jvp(lambda x: fn(x, args)[0], (y,), (jnp.ones_like(y),))[1]

    return slope


def _clipped_newton(fn, slope, y, args, lower, upper):
    """One plain Newton step from `y`, clipped to `[lower, upper]` (the midpoint where it is not finite)."""
    newton = y - fn(y, args)[0] / slope(y, args)
    return jnp.clip(jnp.where(jnp.isfinite(newton), newton, 0.5 * (lower + upper)), lower, upper)


def solve_increasing(
    fn,
    y0,
    args,
    lower,
    upper,
    *,
    tolerance: float,
    max_steps: int,
    unrolled_steps: int = 4,
    slope: Callable | None = None,
):
    """Root of an increasing `fn(y, args)` in `[lower, upper]`; returns `(y, converged)`.

    `fn` returns `(value, aux)`. The first `unrolled_steps` steps (at most `max_steps`) run as
    straight-line code; `optimistix.root_find` takes any steps left after that. `slope(y, args)`,
    if given, is `∂fn/∂y` in closed form, for every step and for the implicit derivative
    (forward-mode differentiation of `fn` otherwise). A closed form can keep each step a single
    XLA loop where the derivative rules of `fn` would not (see the module's docstring).

    Differentiable in `args` by the implicit function theorem, `dy = -(∂fn/∂args · dargs) / (∂fn/∂y)`
    (a `custom_jvp`, so reverse mode works by transposition). Never raises: a solve that runs
    out of steps comes back with `converged = False`, and a non-finite or non-positive slope at
    the root (a point the caller will flag) gives a zero tangent instead of an error, so one
    bad point cannot abort the gradient of a batch.
    """
    slope = slope or _forward_mode_slope(fn)
    return _root(fn, slope, tolerance, max_steps, min(unrolled_steps, max_steps), y0, lower, upper, args)


@functools.partial(jax.custom_jvp, nondiff_argnums=(0, 1, 2, 3, 4))
def _root(fn, slope, tolerance, max_steps, unrolled_steps, y0, lower, upper, args):
    # optimistix (and lineax) take ~0.2 s to import: loaded when a solve is first traced, not by
    # `import jaxcontact` (a warm command-line run reads its programs from disk and traces none).
    import optimistix as optx

    from ._bracketed_newton import BracketedNewton, _BracketState

    y, previous = y0, y0
    for _ in range(unrolled_steps):
        y, previous = _clipped_newton(fn, slope, y, args, lower, upper), y
    solver = BracketedNewton(rtol=tolerance, atol=tolerance, slope=slope)
    options = dict(lower=lower, upper=upper)
    if unrolled_steps:
        # The loop's first check is the last unrolled step's size (the residual is not known here).
        state = _BracketState(lower, upper, y - previous, jnp.full_like(y, jnp.nan), jnp.array(False))
        if max_steps == unrolled_steps:
            return y, solver.terminate(fn, y, args, None, state, None)[0]
        options = dict(state=state)
    sol = optx.root_find(
        fn, solver, y, args, options=options, has_aux=True, max_steps=max_steps - unrolled_steps, throw=False
    )
    return sol.value, sol.result == optx.RESULTS.successful


@_root.defjvp
def _root_jvp(fn, slope, tolerance, max_steps, unrolled_steps, primals, tangents):
    y0, lower, upper, args = primals
    args_dot = tangents[3]
    y, converged = _root(fn, slope, tolerance, max_steps, unrolled_steps, y0, lower, upper, args)
    slope_at_root = slope(y, args)
    _, f_dot = jax.jvp(lambda a: fn(y, a)[0], (args,), (args_dot,))
    good = jnp.isfinite(slope_at_root) & (slope_at_root > 0)
    y_dot = jnp.where(good, -f_dot / jnp.where(good, slope_at_root, 1.0), 0.0)
    return (y, converged), (y_dot, np.zeros(jnp.shape(converged), dtype=jax.dtypes.float0))


class NewtonBisection(eqx.Module):
    """The root finder of a model that solves for each load's state (the largest spot a_l, or GW's
    separation): Newton's method safeguarded by bisection inside a bracket, differentiated by the
    implicit function theorem (`solve_increasing`). A model holds it, as diffrax's implicit solvers
    hold theirs: `Xia2024(root_finder=NewtonBisection(max_steps=16))`.

    **Arguments:** `max_steps`, the cap on steps (1 to 10000; a point that reaches it is flagged
    `NOT_CONVERGED`); `tolerance` on the state's logarithm, None for 64 ε of the working dtype.
    Static: changing them compiles a different program.
    """

    max_steps: int = eqx.field(static=True, default=64)
    tolerance: float | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        steps = self.max_steps
        if isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps <= 10_000:
            raise InputError(f"NewtonBisection: max_steps = {steps!r} must be an integer in [1, 10000]")
        if self.tolerance is not None and not 0.0 < self.tolerance < 1e-2:
            raise InputError(f"NewtonBisection: tolerance = {self.tolerance!r} must be None or in (0, 0.01)")

    def tolerance_for(self, dtype) -> float:
        """The tolerance in the working `dtype`."""
        return self.tolerance or float(64 * jnp.finfo(dtype).eps)

    def find(self, fn, y0, args, lower, upper, *, slope: Callable | None = None):
        """The root of the increasing `fn(y, args)` in `[lower, upper]` from `y0`: `(y, converged)`
        (`solve_increasing`, at this finder's tolerance in the dtype of `y0`)."""
        tolerance = self.tolerance_for(jnp.result_type(y0))
        return solve_increasing(fn, y0, args, lower, upper, tolerance=tolerance, max_steps=self.max_steps, slope=slope)
