"""Many curves at once: one compiled, `vmap`ped fit per curve (and start) with optax's L-BFGS and its
zoom line search on the model's exact gradients (docs/fitting.md, "Many curves at once").

Each curve is fitted as `fitting.fit` fits one: ln-stiffness residuals, the bounded
reparameterisation `s = low + (high − low)·sigmoid(u)`, several starts (a Latin hypercube, the
scene's values one of them), the best kept and finished by Gauss–Newton steps (the optimum of the
least-squares problem itself, as `fit` finds it, not only where L-BFGS's tests stopped); then, per
curve, the statistics `fit` gives (`_batch_result`). The whole batch is one XLA program: on an
accelerator the curves run in parallel.
"""

from __future__ import annotations

import time

import jax
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.core import prepare
from jaxcontact.numerics import float_array, standard_promotion

from ._batch_result import BatchResult, batch_statistics, without
from ._parameters import resolve, stat_of_u
from ._residuals import Observations, observed_residuals, stiffness_curve

# Gauss–Newton steps after L-BFGS (each taken only where it lowers the loss): from where L-BFGS's tests
# stop on the ill-conditioned D–G valley, a few reach the least-squares optimum to round-off.
POLISH_STEPS = 4


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
    u, loss, k, r, ok, status, J = (np.concatenate(parts)[:curves] for parts in zip(*outputs))
    wall_time = time.perf_counter() - t0
    log_stiffness = np.log(stiffness)
    outcome = (u, loss, k, r, ok, status, J)
    result = batch_statistics(fitted, loads, log_stiffness, outcome, max_iter, wall_time, compile_time)
    return without(result, bad)


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


# Compiled batch programs, by scene structure, fitted parameters, settings and argument shapes: a
# second batch of the same shape (other curves, other fixed values) compiles nothing.
_PROGRAMS: dict = {}


def _polished(scene, fitted, data: Observations, u):
    """Gauss–Newton steps from `u` (optimiser coordinates), each kept only where it lowers the loss:
    `(u, loss, r, ok, status, J)` at the best point evaluated, `J = ∂r/∂stat` (statistical coordinates).
    One evaluation of the residuals and their Jacobian per step, the same program each time."""

    def residuals(stat):
        r, ok, status = observed_residuals(stat, scene, fitted, data)
        return r, (r, ok, status)

    def evaluate(u):
        J, (r, ok, status) = jax.jacfwd(residuals, has_aux=True)(stat_of_u(fitted, u))
        return r, ok, status, J

    def step(_, carry):
        trial, best_u, best = carry
        found = evaluate(trial)
        r = found[0].reshape(-1)
        loss = 0.5 * jnp.mean(r * r)
        better = jnp.isfinite(loss) & (loss < best[0])
        best_u = jnp.where(better, trial, best_u)
        best = jax.tree.map(lambda new, old: jnp.where(better, new, old), (loss, *found), best)
        _, r_best, ok_best, _, J_best = best
        used = (ok_best & ~jnp.isnan(data.targets)).reshape(-1)
        # ∂stat/∂u, one coordinate at a time (the map is elementwise): J in optimiser coordinates.
        slope = jax.jvp(lambda x: stat_of_u(fitted, x), (best_u,), (jnp.ones_like(best_u),))[1]
        J_u = jnp.where(used[:, None], J_best.reshape(r.size, -1) * slope[None, :], 0.0)
        delta = jnp.linalg.lstsq(J_u, -jnp.where(used, r_best.reshape(-1), 0.0))[0]
        return best_u + jnp.where(jnp.isfinite(delta), delta, 0.0), best_u, best

    shapes = jax.eval_shape(evaluate, u)
    empty = (jnp.asarray(jnp.inf, u.dtype), *(jnp.zeros(x.shape, x.dtype) for x in shapes))
    _, u, (loss, r, ok, status, J) = jax.lax.fori_loop(0, POLISH_STEPS, step, (u, u, empty))
    return u, loss, r, ok, status, J


def _program(treedef, fitted, max_iter: int, tol: float):
    """(scene leaves, loads, ln K, starts) ↦ vmap over curves of (vmap over starts of the solver, the
    best start polished, its loss, steps, residuals, valid mask, statuses and Jacobian)."""

    def one_curve(scene, loads, log_stiffness, u0s):
        data = stiffness_curve(loads, log_stiffness)
        run = _solver(scene, fitted, data, max_iter, tol)
        us, losses, ks = jax.vmap(run)(u0s)
        best = jnp.argmin(jnp.where(jnp.isfinite(losses), losses, jnp.inf))
        u, loss, r, ok, status, J = _polished(scene, fitted, data, us[best])
        return u, loss, ks[best], r, ok, status, J

    def batch(leaves, loads, log_stiffness, u0s):
        scene = jax.tree_util.tree_unflatten(treedef, leaves)
        return jax.vmap(one_curve, in_axes=(None, 0, 0, None))(scene, loads, log_stiffness, u0s)

    return batch
