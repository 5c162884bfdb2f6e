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
from ._observed import observations
from ._parameters import resolve, stat_of_u
from ._residuals import Observations, observed_residuals

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
    approach=None,
    reference_load=None,
    noise: float | dict[str, float] | None = None,
    n_starts: int = 4,
    seed: int = 0,
    max_iter: int = 100,
    tol: float = 1e-10,
    chunk: int = 32,
) -> BatchResult:
    """Fit `params` to many curves at once, one compiled program for all of them: each curve as `fit`
    fits it (its observables, their weights and statistics), with optax's L-BFGS.

    **Arguments:** `loads` (N, shape (curves, points)); `stiffness` (N/m, the same shape; NaN where only
    the approach was measured; `None` with `approach` alone); `approach` (m, δ(F) − δ(F0), the same
    shape, NaN where not measured); `reference_load` (the preload F0, N: one for all curves or one per
    curve; default each curve's smallest load); `noise` (as `fit`'s: σ of ln K, or a dict by observable);
    `scene` (what is not fitted, shared by the curves, and one start); `params`; `n_starts` (per curve);
    `seed` (of the Latin-hypercube starts); `max_iter`, `tol` (L-BFGS's cap and tolerance on the
    gradient's norm and the loss's relative progress); `chunk` (curves per call of the compiled program:
    a `vmap`ped loop runs until its slowest lane ends, so one start that needs many steps holds its
    chunk, not the batch; on an accelerator a larger chunk fills it better).

    **Returns:** a `BatchResult`. A curve with a value outside its valid range is not fitted (NaN values,
    `success` False, a warning naming the curve and the point); the others are.
    """
    from ._fit import starting_points
    from ._statistics import inner_bounds

    t0 = time.perf_counter()
    fitted = resolve(params)
    if isinstance(n_starts, bool) or not isinstance(n_starts, int) or not 1 <= n_starts <= 64:
        raise InputError(f"n_starts = {n_starts!r} must be an integer in [1, 64]")
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise InputError(f"chunk = {chunk!r} must be a number of curves >= 1")
    dtype = jnp.result_type(1.0)
    loads, data, bad = _curves(loads, stiffness, approach, reference_load, noise, len(fitted), dtype)
    traced, _ = prepare(scene, loads[0])
    own = np.asarray([p.u_from_stat(np.clip(p.to_stat(float(p.get(scene))), *inner_bounds(p))) for p in fitted])
    u0s = jnp.asarray(starting_points(fitted, n_starts, seed, include=own), dtype)
    leaves, treedef = jax.tree_util.tree_flatten(traced)
    curves = len(data)
    size = min(chunk, curves)
    # The last chunk is filled with copies of the first curve (cut off after): one compiled shape.
    stacked = data + [data[0]] * (-curves % size)
    outputs, compile_time = [], 0.0
    for start in range(0, len(stacked), size):
        part = jax.tree.map(lambda *x: jnp.stack(x), *stacked[start : start + size])
        args = (leaves, part, u0s)
        key = (treedef, fitted, max_iter, tol, jax.tree_util.tree_structure(part))
        key += (tuple((x.shape, x.dtype) for x in jax.tree_util.tree_leaves(args)),)
        if key not in _PROGRAMS:
            t1 = time.perf_counter()
            _PROGRAMS[key] = jax.jit(_program(treedef, fitted, max_iter, tol)).lower(*args).compile()
            compile_time += time.perf_counter() - t1
        outputs.append([np.asarray(x) for x in _PROGRAMS[key](*args)])
    outcome = tuple(np.concatenate(parts)[:curves] for parts in zip(*outputs))
    wall_time = time.perf_counter() - t0
    result = batch_statistics(fitted, loads, data, outcome, max_iter, wall_time, compile_time)
    return without(result, bad)


def _curves(loads, stiffness, approach, reference_load, noise, p: int, dtype):
    """`(loads, data, bad)`: the loads (curves, points), each curve's `Observations` (a good curve's
    standing in for a curve that cannot be fitted: one compiled shape) and, by curve, why it cannot."""
    loads = np.atleast_2d(float_array("loads", loads))
    if loads.ndim != 2 or loads.shape[0] == 0:
        raise InputError(f"loads has shape {loads.shape}: give (curves, points), at least one curve")
    if loads.shape[1] <= p:
        raise InputError(f"{loads.shape[1]} points per curve cannot determine {p} parameters")
    given = {k: v for k, v in (("stiffness", stiffness), ("approach", approach)) if v is not None}
    if not given:
        raise InputError("stiffness = None and approach = None: give at least one measured curve per load")
    given = {k: np.atleast_2d(float_array(k, v)) for k, v in given.items()}
    for name, values in given.items():
        if values.shape != loads.shape:
            raise InputError(f"loads {loads.shape} and {name} {values.shape} differ in shape (curves, points)")
    references = np.broadcast_to(
        np.nan if reference_load is None else float_array("reference_load", reference_load), loads.shape[:1]
    )
    bad, data = _bad_points(loads, given), {}
    for c in range(loads.shape[0]):
        if c in bad:
            continue
        try:
            reference = None if np.isnan(references[c]) else float(references[c])
            curve = {k: v[c] for k, v in given.items()}
            data[c], _, _ = observations(
                loads[c], curve.get("stiffness"), curve.get("approach"), reference, noise, dtype, 1
            )
        except InputError as exc:
            bad[c] = f"curve {c}: {exc}"
    if not data:
        raise InputError(f"no curve can be fitted: {bad[0]}")
    good = next(iter(data.values()))
    return loads, [data.get(c, good) for c in range(loads.shape[0])], bad


def _bad_points(loads, given: dict) -> dict[int, str]:
    """By curve, the first point whose load, stiffness or approach is outside its valid range, described
    (a stiffness may be NaN where an approach is given; an approach NaN where not measured)."""
    checks = {
        "loads": lambda v: np.isfinite(v) & (v > 0),
        "stiffness": lambda v: (np.isfinite(v) & (v > 0)) | (np.isnan(v) & ("approach" in given)),
        "approach": lambda v: ~np.isinf(v),
    }
    bad = {}
    for c in range(loads.shape[0]):
        for name, values in (("loads", loads[c]), *((k, v[c]) for k, v in given.items())):
            wrong = np.flatnonzero(~checks[name](values))
            if wrong.size and c not in bad:
                i = int(wrong[0])
                valid = "finite (m) or NaN" if name == "approach" else "positive and finite"
                bad[c] = f"curve {c}, point {i}: {name} = {float(values[i])!r} is not {valid}"
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
        # The normal equations of a few parameters, nudged off singular (a step that does not lower
        # the loss is not kept).
        JTJ = J_u.T @ J_u
        nudge = 1e-12 * jnp.trace(JTJ) * jnp.eye(JTJ.shape[0], dtype=JTJ.dtype)
        delta = jnp.linalg.solve(JTJ + nudge, -J_u.T @ jnp.where(used, r_best.reshape(-1), 0.0))
        return best_u + jnp.where(jnp.isfinite(delta), delta, 0.0), best_u, best

    shapes = jax.eval_shape(evaluate, u)
    empty = (jnp.asarray(jnp.inf, u.dtype), *(jnp.zeros(x.shape, x.dtype) for x in shapes))
    _, u, (loss, r, ok, status, J) = jax.lax.fori_loop(0, POLISH_STEPS, step, (u, u, empty))
    return u, loss, r, ok, status, J


def _program(treedef, fitted, max_iter: int, tol: float):
    """(scene leaves, each curve's `Observations` stacked, starts) ↦ vmap over curves of (vmap over
    starts of the solver, the best start polished, its loss, steps, residuals, valid mask, statuses and
    Jacobian)."""

    def one_curve(scene, data, u0s):
        run = _solver(scene, fitted, data, max_iter, tol)
        us, losses, ks = jax.vmap(run)(u0s)
        best = jnp.argmin(jnp.where(jnp.isfinite(losses), losses, jnp.inf))
        u, loss, r, ok, status, J = _polished(scene, fitted, data, us[best])
        # Every start's end, the best one polished: where the others ended says whether a distinct
        # optimum fits almost as well (`rival_optima`).
        return u, loss, ks[best], r, ok, status, J, us.at[best].set(u), losses.at[best].set(loss)

    def batch(leaves, data, u0s):
        scene = jax.tree_util.tree_unflatten(treedef, leaves)
        return jax.vmap(one_curve, in_axes=(None, 0, None))(scene, data, u0s)

    return batch
