"""Fitting fractal surface parameters to measured stiffness-vs-load curves.

The loss is on log stiffness (relative errors, as measurement noise on K usually is):
`r_i = ln K_model(F_i; θ) - ln K_i`. Several starts, spread over the parameter bounds, are
optimised together (vmapped) and the best is kept. Uncertainty is the Gauss–Newton covariance
at the optimum, `s² (JᵀJ)⁻¹` with `s² = Σr²/(N - p)`, formed in statistical coordinates (D and
ν linear; G, E, H, l_min, area logarithmic), with Student-t 95 % intervals.

Data points that the model cannot evaluate at a trial θ (interaction breakdown, load out of
range) contribute a constant residual `FLAGGED_RESIDUAL` with no gradient, so that no start can
win by pushing points out of the model; at the optimum such points are excluded from the
statistics and named in `FitResult.warnings`.
"""

from __future__ import annotations

import dataclasses
import math
import time

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optax
import optimistix as optx
from scipy import stats

import jaxcontact as jc
from jaxcontact.solve import prepare

from .parameters import FitParameter, resolve, with_stat

FLAGGED_RESIDUAL = 1.0  # a miss by a factor e in stiffness
METHODS = ("lbfgs", "lm")
# float64. LM's test is on the relative step, which must sit above the round-off of steps along
# the ill-conditioned D–G valley: at 1e-12 a single start can wander for its 400 iterations on
# ulps (it did on the 30-point bench curve), at 1e-10 it stops in 11 at the same D to 1e-10.
DEFAULT_TOLERANCE = {"lbfgs": 1e-12, "lm": 1e-10}


@dataclasses.dataclass(frozen=True)
class FitResult:
    """Estimates, their uncertainty, and how the fit went.

    **Fields:** `values`, `stderr`, `ci95` (dicts by parameter name; stderr of a log-coordinate
    parameter is the delta-method value · se(ln value), its interval is exp(ln value ± t·se));
    `correlation` and `covariance` (in statistical coordinates, ordered as `params`);
    `residuals` (ln K_model − ln K_data at the optimum, NaN at flagged points); `flagged`
    (indices of data points outside the model at the optimum); `success`; `iterations` (of the
    best start); `wall_time` (s, compilation included); `warnings`; `condition_number` (of the
    scaled Gauss–Newton matrix); `start_losses`; `scene` (the fitted scene).
    """

    params: tuple[str, ...]
    values: dict
    stderr: dict
    ci95: dict
    correlation: np.ndarray
    covariance: np.ndarray
    residuals: np.ndarray
    flagged: np.ndarray
    success: bool
    iterations: int
    wall_time: float
    warnings: tuple[str, ...]
    condition_number: float
    loss: float
    start_losses: np.ndarray
    method: str
    scene: jc.Scene = dataclasses.field(repr=False)

    def summary(self) -> str:
        lines = [f"fit by {self.method}: {'converged' if self.success else 'NOT converged'} in {self.iterations} "
                 f"iterations, {self.wall_time:.2f} s; rms log residual {math.sqrt(2 * self.loss):.3g}"]
        for name in self.params:
            lo, hi = self.ci95[name]
            lines.append(f"  {name:6s} = {self.values[name]:.6g} ± {self.stderr[name]:.3g}   95% CI [{lo:.6g}, {hi:.6g}]")
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"params": list(self.params), "values": self.values, "stderr": self.stderr,
                "ci95": {k: list(v) for k, v in self.ci95.items()}, "correlation": self.correlation.tolist(),
                "residuals": self.residuals.tolist(), "flagged": self.flagged.tolist(), "success": self.success,
                "iterations": self.iterations, "wall_time_s": self.wall_time, "warnings": list(self.warnings),
                "condition_number": self.condition_number, "loss": self.loss, "method": self.method}


def log_residuals(stat, scene, params, loads, log_stiffness):
    """`(r, ok)`: log-stiffness residuals at statistical coordinates `stat`, and the valid mask."""
    r, ok, _ = _residuals_and_status(stat, scene, params, loads, log_stiffness)
    return r, ok


def _residuals_and_status(stat, scene, params, loads, log_stiffness):
    sol = jc.solve(with_stat(scene, params, stat), loads)
    ok = sol.ok & (sol.stiffness > 0)
    K = jnp.where(ok, sol.stiffness, 1.0)  # no log of NaN or 0: no NaN in any gradient
    return jnp.where(ok, jnp.log(K) - log_stiffness, FLAGGED_RESIDUAL), ok, sol.status


def _stat_from_u(params, u):
    return jnp.stack([p.stat_from_u(u[i]) for i, p in enumerate(params)])


def _residual_fn(scene, params, data):
    loads, log_stiffness, weights = data
    def residuals(u):
        return weights * log_residuals(_stat_from_u(params, u), scene, params, loads, log_stiffness)[0]
    return residuals


def _run_lbfgs(residuals, n_points, u0, max_iter, tol):
    def loss(u):
        r = residuals(u)
        return 0.5 * jnp.sum(r * r) / n_points

    opt = optax.lbfgs()
    value_and_grad = optax.value_and_grad_from_state(loss)

    def step(carry):
        u, state, _, value_before = carry
        value, grad = value_and_grad(u, state=state)
        updates, state = opt.update(grad, state, u, value=value, grad=grad, value_fn=loss)
        return optax.apply_updates(u, updates), state, value_before, value

    def done(state, previous, current):
        # Stationary, or stalled: at a kink of the loss (a_l crossing a regime boundary as the
        # parameters move) the gradient never becomes small, but the line search stops gaining.
        small_gradient = optax.tree.norm(optax.tree.get(state, "grad")) < tol
        stalled = jnp.abs(previous - current) <= 1e-14 * jnp.abs(current) + tol * tol
        return small_gradient | stalled

    def keep_going(carry):
        _, state, previous, current = carry
        count = optax.tree.get(state, "count")
        return (count < 2) | ((count < max_iter) & ~done(state, previous, current))

    inf = jnp.array(jnp.inf, u0.dtype)
    u, state, previous, current = jax.lax.while_loop(keep_going, step, (u0, opt.init(u0), inf, inf))
    return u, loss(u), optax.tree.get(state, "count"), done(state, previous, current)


def _run_lm(residuals, n_points, u0, max_iter, tol):
    solver = optx.LevenbergMarquardt(rtol=tol, atol=tol)
    sol = optx.least_squares(lambda u, _: residuals(u), solver, u0, max_steps=max_iter, throw=False)
    r = residuals(sol.value)
    return sol.value, 0.5 * jnp.sum(r * r) / n_points, sol.stats["num_steps"], sol.result == optx.RESULTS.successful


# Curves are padded to a multiple of this many points (padding points weigh nothing), and the
# starts to a multiple of this many lanes (padding lanes repeat the first start and are dropped),
# so that fits of curves of different lengths, with different numbers of starts and different
# fixed parameter values (the scene's floats are traced), share one compiled optimiser. With
# interaction "paper" it takes ~20 s (LM) or ~35 s (L-BFGS) to compile, and a fit 0.01-2 s to run.
POINTS_MULTIPLE = 64
STARTS_MULTIPLE = 16


def _padded(values: np.ndarray, multiple: int) -> np.ndarray:
    """`values` (along the first axis), padded to a multiple of `multiple` with copies of the first."""
    return np.concatenate([values, np.repeat(values[:1], -len(values) % multiple, axis=0)])


def _padded_curve(loads, stiffness, dtype):
    """`(loads, ln stiffness, weights)`, padded; padding points repeat the first, with weight 0."""
    weights = _padded(np.ones_like(loads), POINTS_MULTIPLE)
    weights[len(loads):] = 0.0
    return (jnp.asarray(_padded(loads, POINTS_MULTIPLE), dtype),
            jnp.log(jnp.asarray(_padded(stiffness, POINTS_MULTIPLE), dtype)), jnp.asarray(weights, dtype))


@eqx.filter_jit
def _multistart(method, scene, params, data, u0s, max_iter, tol):
    residuals = _residual_fn(scene, params, data)
    n_points = jnp.sum(data[2])
    run = _run_lbfgs if method == "lbfgs" else _run_lm
    return jax.vmap(lambda u0: run(residuals, n_points, u0, max_iter, tol))(u0s)


@eqx.filter_jit
def _residuals_and_jacobian(stat, scene, params, loads, log_stiffness):
    """Residuals, valid mask, status and d(residual)/d(stat) at `stat` (Gauss–Newton statistics)."""
    def residuals(s):
        r, ok, status = _residuals_and_status(s, scene, params, loads, log_stiffness)
        return r, (r, ok, status)
    J, (r, ok, status) = jax.jacfwd(residuals, has_aux=True)(stat)
    return r, ok, status, J


def starting_points(params, n_starts: int, seed: int, include=None) -> np.ndarray:
    """Starts in optimiser coordinates: a Latin hypercube over 2 %…98 % of each bound (plus `include`)."""
    rng = np.random.default_rng(seed)
    fractions = (rng.permuted(np.tile(np.arange(n_starts), (len(params), 1)), axis=1).T
                 + rng.uniform(size=(n_starts, len(params)))) / n_starts
    fractions = 0.02 + 0.96 * fractions
    u = np.log(fractions) - np.log1p(-fractions)
    if include is not None:
        u = np.vstack([np.asarray(include)[None, :], u[:-1]])
    return u


def fit(loads, stiffness, scene: jc.Scene, params=("D", "G"), method: str = "lbfgs", *, n_starts: int = 12,
        seed: int = 0, max_iter: int = 400, tol: float | None = None, starts=None) -> FitResult:
    """Fit scene parameters to a stiffness-vs-load curve.

    **Arguments:**

    - `loads`, `stiffness`: the measured curve, N and N/m (1-D, same length, all positive).
    - `scene`: a `jaxcontact.Scene` supplying everything that is not fitted (and one start).
    - `params`: names of the fitted float fields: any of D, G, l_min, E, nu, H, area.
    - `method`: "lbfgs" (optax L-BFGS on the mean squared log residual) or "lm" (optimistix
      Levenberg–Marquardt on the residual vector).
    - `n_starts`: number of starts optimised together (vmapped); the scene's own values are one.
      Several are needed: where a_l crosses a regime boundary as the parameters move, the loss has
      kinks, and along the strongly correlated D–G valley a single start can stall at one. They
      run in lanes padded to a multiple of 16 (one start costs as much arithmetic as 16, and fits
      with 1 to 16 starts share one compiled optimiser).
    - `seed`: seed of the Latin-hypercube starts.
    - `max_iter`, `tol`: iteration cap and tolerance (gradient norm for L-BFGS, relative step and
      residual for LM); `None` picks 1e-12 for L-BFGS and 1e-10 for LM in float64, 1e-6 in float32.
    - `starts`: explicit starts, an array of shape (n, len(params)) of physical values.

    **Returns:** a `FitResult`.
    """
    t0 = time.perf_counter()
    if method not in METHODS:
        raise ValueError(f"method = {method!r} is not one of {', '.join(map(repr, METHODS))}")
    fitted: tuple[FitParameter, ...] = resolve(params)
    loads = np.asarray(loads, dtype=float).reshape(-1)
    stiffness = np.asarray(stiffness, dtype=float).reshape(-1)
    if loads.shape != stiffness.shape:
        raise ValueError(f"loads ({loads.size}) and stiffness ({stiffness.size}) differ in length")
    if loads.size <= len(fitted):
        raise ValueError(f"{loads.size} data points cannot determine {len(fitted)} parameters")
    for name, values in (("loads", loads), ("stiffness", stiffness)):
        if not np.all(np.isfinite(values) & (values > 0)):
            raise ValueError(f"{name} must be positive and finite (valid range (0, inf))")
    dtype = jnp.result_type(1.0)
    if tol is None:
        tol = DEFAULT_TOLERANCE[method] if dtype == jnp.float64 else 1e-6
    own = np.asarray([float(p.u_from_stat(jnp.clip(p.to_stat(float(p.get(scene))), *_inner(p)))) for p in fitted])
    if starts is None:
        u0s = starting_points(fitted, n_starts, seed, include=own)
    else:
        starts = np.atleast_2d(np.asarray(starts, dtype=float))
        u0s = np.stack([[float(p.u_from_stat(p.to_stat(v))) for p, v in zip(fitted, row)] for row in starts])
    traced_scene, _ = prepare(scene, loads)
    data = _padded_curve(loads, stiffness, dtype)
    lanes = _multistart(method, traced_scene, fitted, data, jnp.asarray(_padded(u0s, STARTS_MULTIPLE), dtype),
                        max_iter, tol)
    u_all, losses, counts, converged = (x[:len(u0s)] for x in lanes)
    losses = np.asarray(losses)
    best = int(np.nanargmin(np.where(np.isfinite(losses), losses, np.inf)))
    stat_hat = _stat_from_u(fitted, u_all[best])
    result = _statistics(traced_scene, fitted, loads, data, stat_hat, np.asarray(u_all[best]))
    success = bool(converged[best]) and np.isfinite(losses[best]) and result["n_used"] > len(fitted)
    warnings = list(result["warnings"]) + _rival_optima(fitted, u_all, losses, best, loads.size, result)
    if not bool(converged[best]):
        warnings.insert(0, f"the best start did not converge in {max_iter} iterations")
    return FitResult(
        params=tuple(p.name for p in fitted), values=result["values"], stderr=result["stderr"], ci95=result["ci95"],
        correlation=result["correlation"], covariance=result["covariance"], residuals=result["residuals"],
        flagged=result["flagged"], success=success, iterations=int(counts[best]), wall_time=time.perf_counter() - t0,
        warnings=tuple(warnings), condition_number=result["condition"], loss=float(losses[best]),
        start_losses=losses, method=method, scene=with_stat(scene, fitted, np.asarray(stat_hat)),
    )


def _rival_optima(params, u_all, losses, best, n_points, result) -> list[str]:
    """Warn when another start ended at a clearly distinct optimum that fits almost as well.

    A local Gauss–Newton interval cannot describe a bimodal misfit; this model has such cases
    (e.g. a second (D, G) with a_c near the cutoff when the curve stays above F* ≈ 1e-9).
    Distinct: Mahalanobis distance > 5 under the covariance; almost as well: Δχ² < 9.
    """
    covariance = result["covariance"]
    if not np.all(np.isfinite(covariance)):
        return []
    rss = 2.0 * n_points * np.asarray(losses)
    s2 = rss[best] / max(result["n_used"] - len(params), 1)
    stats_all = np.asarray(jax.vmap(lambda u: _stat_from_u(params, u))(u_all))
    precision = np.linalg.pinv(covariance)
    rivals = []
    for k in range(len(losses)):
        delta = stats_all[k] - stats_all[best]
        if k == best or not np.isfinite(rss[k]) or float(delta @ precision @ delta) <= 25.0:
            continue
        # An exact fit (s2 = 0) makes any worse minimum infinitely worse, and another exact one equal.
        chi2 = (rss[k] - rss[best]) / s2 if s2 > 0 else (0.0 if rss[k] <= rss[best] else math.inf)
        if chi2 < 9.0:
            rivals.append((chi2, k))
    if not rivals:
        return []
    chi2, k = min(rivals)
    where = ", ".join(f"{p.name} = {float(p.from_stat(stats_all[k][i])):.4g}" for i, p in enumerate(params))
    return [f"a distinct optimum ({where}) fits almost as well (Δχ² = {chi2:.2f}): the data do not choose between "
            "them, and the intervals above describe only the best one; extend the load range (to lower F*) or "
            "add points"]


def _inner(p: FitParameter):
    lo, hi = p.stat_bounds
    return lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo)


def _statistics(scene, params, loads, data, stat_hat, u_hat) -> dict:
    """Gauss–Newton covariance, intervals, correlations and identifiability warnings at the optimum.

    `loads` is the curve as given; `data` is `_padded_curve`'s, whose padding is cut off here.
    """
    padded_loads, log_stiffness, _ = data
    r, ok, status, J = (np.asarray(x)[:loads.size]
                        for x in _residuals_and_jacobian(stat_hat, scene, params, padded_loads, log_stiffness))
    warnings = []
    flagged = np.flatnonzero(~ok)
    if flagged.size:
        status = status[flagged]
        listed = ", ".join(f"{loads[i]:.4g} N ({jc.status_message(s)})" for i, s in zip(flagged[:5], status[:5]))
        warnings.append(f"{flagged.size} of {loads.size} points are outside the model at the optimum and were "
                        f"left out of the statistics: {listed}{' …' if flagged.size > 5 else ''}")
    J, r_used = J[ok], r[ok]
    n, p = J.shape
    dof = n - p
    names = [q.name for q in params]
    nan_matrix = np.full((p, p), np.nan)
    covariance, correlation, condition = nan_matrix, nan_matrix, math.inf
    if dof > 0:
        s2 = float(r_used @ r_used) / dof
        JTJ = J.T @ J
        scale = np.sqrt(np.diag(JTJ))
        if np.all(scale > 0):
            scaled = JTJ / np.outer(scale, scale)
            condition = float(np.linalg.cond(scaled))
            inverse = np.linalg.pinv(JTJ)
            covariance = s2 * inverse
            # From the inverse itself: the correlation does not depend on the residuals' scale,
            # and an exact fit (s2 = 0, every standard error 0) still has one.
            spread = np.sqrt(np.diag(inverse))
            correlation = inverse / np.outer(spread, spread)
        else:
            warnings.append("the data do not depend on "
                            + ", ".join(names[i] for i in np.flatnonzero(scale == 0)) + ": not identifiable")
    else:
        warnings.append(f"{n} usable points for {p} parameters: no uncertainty can be estimated")
    t = stats.t.ppf(0.975, dof) if dof > 0 else math.nan
    values, stderr, ci95 = {}, {}, {}
    for i, q in enumerate(params):
        s, se = float(stat_hat[i]), math.sqrt(covariance[i, i]) if np.isfinite(covariance[i, i]) else math.nan
        values[q.name] = float(q.from_stat(s))
        stderr[q.name] = values[q.name] * se if q.log else se
        ci95[q.name] = (float(q.from_stat(s - t * se)), float(q.from_stat(s + t * se)))
        if abs(u_hat[i]) > 12:
            warnings.append(f"{q.name} = {values[q.name]:.4g} is at the edge of its bounds [{q.low:g}, {q.high:g}]")
    for i in range(p):
        for j in range(i + 1, p):
            if abs(correlation[i, j]) > 0.99:
                warnings.append(f"{names[i]} and {names[j]} are strongly correlated (r = {correlation[i, j]:+.4f}): "
                                "poorly identified separately")
    if condition > 1e8:
        warnings.append(f"the Gauss–Newton matrix is ill-conditioned (condition number {condition:.3g})")
    residuals = np.where(ok, r, np.nan)
    return dict(values=values, stderr=stderr, ci95=ci95, covariance=covariance, correlation=correlation,
                condition=condition, warnings=warnings, flagged=flagged, residuals=residuals, n_used=n)
