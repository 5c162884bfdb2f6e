"""Many curves at once: one compiled, `vmap`ped fit per curve (and start) with optax's L-BFGS and its
zoom line search on the model's exact gradients (docs/fitting.md, "Many curves at once").

Each curve is fitted as `fitting.fit` fits one: ln-stiffness residuals, the bounded
reparameterisation `s = low + (high − low)·sigmoid(u)`, several starts (a Latin hypercube, the
scene's values one of them), the best kept; then the Gauss–Newton covariance at its optimum, Student-t
intervals and the identifiability of its combinations, per curve. The whole batch is one XLA program:
on an accelerator the curves run in parallel.
"""

from __future__ import annotations

import dataclasses
import math
import time

import jax
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.core import prepare
from jaxcontact.numerics import float_array, standard_promotion

from ._identifiability import combinations
from ._parameters import resolve, stat_of_u
from ._residuals import Observations, observed_residuals, stiffness_curve
from ._statistics import NOTHING_DETERMINED, bounds_reached, nothing_determined, stderr_and_interval, student_t


@dataclasses.dataclass(frozen=True)
class BatchResult:
    """Per curve (leading axis of every array): `values`, `stderr`, `ci95` (dicts by name of arrays;
    `ci95[name]` has shape (curves, 2)), `correlation` (curves, p, p), `loss` (½ mean r²), `iterations`,
    `success` (converged, finite, enough valid points, no parameter on a search bound, and some
    combination of the parameters determined: a curve of pure noise is not a success), `flagged`
    (valid-point mask is its negation: shape (curves, points)), `determined` (curves, p: whether each
    Fisher combination is determined), `warnings` (a tuple of strings per curve), `wall_time` (s,
    compilation included) and `compile_time` (0 where a batch of the same shape was compiled before in this process)."""

    params: tuple[str, ...]
    values: dict
    stderr: dict
    ci95: dict
    correlation: np.ndarray
    loss: np.ndarray
    iterations: np.ndarray
    success: np.ndarray
    flagged: np.ndarray
    determined: np.ndarray
    warnings: tuple
    wall_time: float
    compile_time: float


def _solver(scene, fitted, data: Observations, max_iter: int, tol: float):
    """One curve's fit from one start `u0`: optax L-BFGS until the gradient's norm or the loss's relative
    progress falls below `tol`, or `max_iter` steps."""
    import optax

    def loss(u):
        r, _, _ = observed_residuals(stat_of_u(fitted, u), scene, fitted, data)
        return 0.5 * jnp.mean(r * r)

    optimiser = optax.lbfgs()

    # The line search leaves the value and gradient at its accepted point in the state: the next
    # step takes them from there. (`optax.value_and_grad_from_state` would do it by a `cond`, which
    # under `vmap` computes the gradient again on every step.)
    def body(carry):
        u, state, value, grad, _, k = carry
        updates, state = optimiser.update(grad, state, u, value=value, grad=grad, value_fn=loss)
        new_value = optax.tree_utils.tree_get(state, "value")
        new_grad = optax.tree_utils.tree_get(state, "grad")
        return optax.apply_updates(u, updates), state, new_value, new_grad, value, k + 1

    def going(carry):
        _, _, value, grad, previous, k = carry
        small = (jnp.linalg.norm(grad) < tol) | (jnp.abs(previous - value) <= tol * jnp.abs(value))
        return (k < max_iter) & ~((k > 2) & small)

    def run(u0):
        value, grad = jax.value_and_grad(loss)(u0)
        with standard_promotion():
            init = (u0, optimiser.init(u0), value, grad, jnp.asarray(jnp.inf, u0.dtype), 0)
            u, _, value, _, _, k = jax.lax.while_loop(going, body, init)
        return u, value, k

    return run


def fit_batch(
    loads,
    stiffness,
    scene: jc.Scene,
    params=("D", "G"),
    *,
    n_starts: int = 4,
    seed: int = 0,
    max_iter: int = 100,
    tol: float = 1e-10,
    chunk: int = 32,
) -> BatchResult:
    """Fit `params` to many stiffness curves at once, one compiled program for all of them.

    **Arguments:** `loads`, `stiffness` (N, N/m; shape (curves, points), all positive); `scene` (what is not
    fitted, shared by the curves, and one start); `params`; `n_starts` (per curve); `seed` (of the
    Latin-hypercube starts); `max_iter`, `tol` (L-BFGS's cap and tolerance on the gradient's norm and the
    loss's relative progress); `chunk` (curves per call of the compiled program: a `vmap`ped loop runs
    until its slowest lane ends, so one start that needs many steps holds its chunk, not the batch; on
    an accelerator a larger chunk fills it better).

    **Returns:** a `BatchResult`. A curve with a load or stiffness that is not positive and finite is
    not fitted (NaN values, `success` False, a warning naming the curve and the point); the others are.
    """
    from ._fit import starting_points
    from ._statistics import inner_bounds

    t0 = time.perf_counter()
    fitted = resolve(params)
    loads, stiffness = (np.atleast_2d(float_array(k, v)) for k, v in (("loads", loads), ("stiffness", stiffness)))
    if loads.ndim != 2 or loads.shape[0] == 0:
        raise InputError(f"loads has shape {loads.shape}: give (curves, points), at least one curve")
    if loads.shape != stiffness.shape:
        raise InputError(f"loads {loads.shape} and stiffness {stiffness.shape} differ in shape (curves, points)")
    if loads.shape[1] <= len(fitted):
        raise InputError(f"{loads.shape[1]} points per curve cannot determine {len(fitted)} parameters")
    bad = _bad_points(loads, stiffness)
    if len(bad) == loads.shape[0]:
        raise InputError(f"no curve can be fitted: {bad[0]} (valid range (0, inf))")
    if isinstance(n_starts, bool) or not isinstance(n_starts, int) or not 1 <= n_starts <= 64:
        raise InputError(f"n_starts = {n_starts!r} must be an integer in [1, 64]")
    traced, _ = prepare(scene, loads[0])
    dtype = jnp.result_type(1.0)
    own = np.asarray([p.u_from_stat(np.clip(p.to_stat(float(p.get(scene))), *inner_bounds(p))) for p in fitted])
    u0s = jnp.asarray(starting_points(fitted, n_starts, seed, include=own), dtype)
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise InputError(f"chunk = {chunk!r} must be a number of curves >= 1")
    leaves, treedef = jax.tree_util.tree_flatten(traced)
    # A curve with a bad point is not fitted: a good curve stands in for it (one compiled shape), and
    # its result is NaN with a warning that names the point.
    good = next(c for c in range(loads.shape[0]) if c not in bad)
    stand_in = np.array([good if c in bad else c for c in range(loads.shape[0])])
    loads, stiffness = loads[stand_in], stiffness[stand_in]
    curves = loads.shape[0]
    size = min(chunk, curves)
    # The last chunk is filled with copies of the first curve (cut off after): one compiled shape.
    padded = lambda a: np.concatenate([a, np.repeat(a[:1], -curves % size, axis=0)])  # noqa: E731
    all_loads, all_log_stiffness = padded(loads), padded(np.log(stiffness))
    outputs, compile_time = [], 0.0
    for start in range(0, all_loads.shape[0], size):
        part = slice(start, start + size)
        args = (leaves, jnp.asarray(all_loads[part], dtype), jnp.asarray(all_log_stiffness[part], dtype), u0s)
        key = (treedef, fitted, max_iter, tol, tuple((x.shape, x.dtype) for x in jax.tree_util.tree_leaves(args)))
        if key not in _PROGRAMS:
            t1 = time.perf_counter()
            _PROGRAMS[key] = jax.jit(_program(treedef, fitted, max_iter, tol)).lower(*args).compile()
            compile_time += time.perf_counter() - t1
        outputs.append([np.asarray(x) for x in _PROGRAMS[key](*args)])
    u, loss, k, r, ok, J = (np.concatenate(parts)[:curves] for parts in zip(*outputs))
    result = _statistics(fitted, u, loss, k, r, ok, J, max_iter, time.perf_counter() - t0, compile_time)
    return _without(result, bad)


def _bad_points(loads, stiffness) -> dict[int, str]:
    """By curve, the first point whose load or stiffness is not positive and finite, described."""
    bad = {}
    for c in range(loads.shape[0]):
        for name, values in (("loads", loads[c]), ("stiffness", stiffness[c])):
            wrong = np.flatnonzero(~(np.isfinite(values) & (values > 0)))
            if wrong.size and c not in bad:
                i = int(wrong[0])
                bad[c] = f"curve {c}, point {i}: {name} = {float(values[i])!r} is not positive and finite"
    return bad


def _without(result: BatchResult, bad: dict[int, str]) -> BatchResult:
    """`result` with the curves in `bad` unfitted: NaN values and intervals, success False, the reason."""
    if not bad:
        return result
    rows = list(bad)
    values, stderr, ci95 = ({k: v.copy() for k, v in d.items()} for d in (result.values, result.stderr, result.ci95))
    for d in (values, stderr, ci95):
        for v in d.values():
            v[rows] = np.nan
    correlation, loss, success = result.correlation.copy(), result.loss.copy(), result.success.copy()
    correlation[rows], loss[rows], success[rows] = np.nan, np.nan, False
    flagged, determined = result.flagged.copy(), result.determined.copy()
    flagged[rows], determined[rows] = True, False
    warnings = tuple((f"{bad[c]}: the curve was not fitted",) if c in bad else w for c, w in enumerate(result.warnings))
    return dataclasses.replace(
        result,
        values=values,
        stderr=stderr,
        ci95=ci95,
        correlation=correlation,
        loss=loss,
        success=success,
        flagged=flagged,
        determined=determined,
        warnings=warnings,
    )


# Compiled batch programs, by scene structure, fitted parameters, settings and argument shapes: a
# second batch of the same shape (other curves, other fixed values) compiles nothing.
_PROGRAMS: dict = {}


def _program(treedef, fitted, max_iter: int, tol: float):
    """(scene leaves, loads, ln K, starts) ↦ vmap over curves of (vmap over starts of the solver, the
    best start, its residuals and Jacobian)."""

    def one_curve(scene, loads, log_stiffness, u0s):
        data = stiffness_curve(loads, log_stiffness)
        run = _solver(scene, fitted, data, max_iter, tol)
        us, losses, ks = jax.vmap(run)(u0s)
        best = jnp.argmin(jnp.where(jnp.isfinite(losses), losses, jnp.inf))
        stat = stat_of_u(fitted, us[best])

        def residuals(s):
            r, ok, _ = observed_residuals(s, scene, fitted, data)
            return r[:, 0], (r[:, 0], ok[:, 0])

        J, (r, ok) = jax.jacfwd(residuals, has_aux=True)(stat)
        return us[best], losses[best], ks[best], r, ok, J

    def batch(leaves, loads, log_stiffness, u0s):
        scene = jax.tree_util.tree_unflatten(treedef, leaves)
        return jax.vmap(one_curve, in_axes=(None, 0, 0, None))(scene, loads, log_stiffness, u0s)

    return batch


def _statistics(fitted, u, loss, k, r, ok, J, max_iter, wall_time, compile_time) -> BatchResult:
    """Per curve: Gauss–Newton covariance on its valid points, Student-t intervals, identifiability, warnings."""
    p = len(fitted)
    curves = u.shape[0]
    stat = np.array([[q.stat_from_u(x) for q, x in zip(fitted, row)] for row in u])
    values = {q.name: np.array([float(q.from_stat(s)) for s in stat[:, i]]) for i, q in enumerate(fitted)}
    stderr = {q.name: np.full(curves, np.nan) for q in fitted}
    ci95 = {q.name: np.full((curves, 2), np.nan) for q in fitted}
    correlation = np.full((curves, p, p), np.nan)
    determined = np.zeros((curves, p), bool)
    unusable = np.zeros(curves, bool)
    warnings = []
    for c in range(curves):
        used = ok[c]
        n = int(used.sum())
        notes = []
        if k[c] >= max_iter:
            notes.append(f"did not converge in {max_iter} L-BFGS steps")
        if n < r.shape[1]:
            notes.append(f"{r.shape[1] - n} of {r.shape[1]} points are outside the model at the optimum")
        if n > p:
            Jc, rc = J[c][used], r[c][used]
            s2 = float(rc @ rc) / (n - p)
            JTJ = Jc.T @ Jc
            if np.linalg.matrix_rank(JTJ) == p and s2 > 0:
                inverse = np.linalg.inv(JTJ)
                spread = np.sqrt(np.diag(inverse))
                correlation[c] = inverse / np.outer(spread, spread)
                t = student_t(n - p)
                for i, q in enumerate(fitted):
                    se = math.sqrt(s2 * inverse[i, i])
                    stderr[q.name][c], ci95[q.name][c] = stderr_and_interval(q, stat[c, i], se, t)
                found = combinations(fitted, JTJ / s2)
                determined[c] = [f.determined for f in found]
                if nothing_determined(found):
                    notes.append(NOTHING_DETERMINED)
                    unusable[c] = True
                elif not all(determined[c]):
                    notes.append("the curve leaves a combination of the parameters open (see `determined`)")
        bounds = bounds_reached(fitted, stat[c], r[c][used], J[c][used])
        unusable[c] |= bool(bounds)
        notes += bounds
        warnings.append(tuple(notes))
    success = (k < max_iter) & np.isfinite(loss) & (ok.sum(axis=1) > p) & ~unusable
    return BatchResult(
        params=tuple(q.name for q in fitted),
        values=values,
        stderr=stderr,
        ci95=ci95,
        correlation=correlation,
        loss=np.asarray(loss, dtype=float),
        iterations=np.asarray(k),
        success=success,
        flagged=~ok,
        determined=determined,
        warnings=tuple(warnings),
        wall_time=wall_time,
        compile_time=compile_time,
    )
