"""Fitting fractal surface parameters to measured stiffness-vs-load curves.

The loss is on log stiffness (relative errors, as measurement noise on K usually is):
`r_i = ln K_model(F_i; θ) - ln K_i`. Several starts, spread over the parameter bounds, are
optimised one after another (scipy's optimisers on the host, `jaxcontact.fitting._optimise`, each call one
run of the compiled model and its Jacobian) and the best is kept. Uncertainty is the
Gauss–Newton covariance at the optimum, `s² (JᵀJ)⁻¹` with `s² = Σr²/(N - p)`, formed in
statistical coordinates (D and ν linear; G, E, H, l_min, area logarithmic), with Student-t 95 %
intervals.

Data points that the model cannot evaluate at a trial θ (interaction breakdown, load out of
range) contribute a constant residual `FLAGGED_RESIDUAL` with no gradient, so that no start can
win by pushing points out of the model; at the optimum such points are excluded from the
statistics and named in `FitResult.warnings`.
"""

from __future__ import annotations

import time

import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.core import prepare
from jaxcontact.numerics import check_strategy, float_array

from ._identifiability import profiles_of
from ._observed import POINTS_MULTIPLE, observations
from ._optimise import BFGS, METHODS, AbstractMethod, Objective, stalled
from ._parameters import resolve, with_stat
from ._prior import PriorObjective, noise_scale, with_prior
from ._problem import Problem
from ._residuals import evaluated
from ._result import FitResult
from ._statistics import rival_optima, statistics


def _multiple(scene) -> int:
    """The curve's padding: `POINTS_MULTIPLE`, or none for a model that does not pad its loads."""
    return POINTS_MULTIPLE if scene.model.pad_loads else 1


def fit(
    loads,
    stiffness,
    scene: jc.Scene,
    params=("D", "G"),
    method: AbstractMethod = BFGS(),
    *,
    n_starts: int = 12,
    seed: int = 0,
    max_iter: int = 400,
    tol: float | None = None,
    starts=None,
    prior=None,
    noise: float | dict[str, float] | None = None,
    profile: bool = False,
    approach=None,
    reference_load: float | None = None,
) -> FitResult:
    """Fit scene parameters to a stiffness-vs-load curve, an approach-vs-load curve, or both.

    **Arguments:**

    - `loads`, `stiffness`: the measured curve, N and N/m (1-D, same length, all positive); `stiffness`
      may be `None` when `approach` is given, and NaN at loads where only the approach was measured.
    - `approach`: the measured approach δ(F) − δ(F0) (m) at the same loads (docs/model.md §6), NaN
      where not measured; fitted alone or together with `stiffness`.
    - `reference_load`: the preload F0 (N) that the approach is measured from (default: the smallest
      load, where the approach must then be 0).
    - `scene`: a `jaxcontact.Scene` supplying everything that is not fitted (and one start).
    - `params`: names of the fitted float fields: any of D, G, l_min, E, nu, H, area.
    - `method`: `BFGS()` (quasi-Newton BFGS on the mean squared log residual, scipy's L-BFGS-B) or
      `LevenbergMarquardt()` (on the residual vector, MINPACK through `scipy.optimize.least_squares`).
    - `n_starts`: number of starts, optimised one after another; the scene's own values are one.
      Several are needed: where a_l crosses a regime boundary as the parameters move, the loss has
      kinks, and along the strongly correlated D–G valley a single start can stall at one.
    - `seed`: seed of the Latin-hypercube starts.
    - `max_iter`, `tol`: the cap on iterations (BFGS) or on evaluations of the residuals (LM), and
      the tolerance (BFGS: on the loss's relative progress per iteration and on the gradient; LM:
      MINPACK's `xtol`, `ftol` and `gtol`); `None` picks 1e-15 for BFGS and 1e-10 for LM in
      float64, 1e-6 in float32, and never finer than the model's `precision` ε (1e-6 for the
      boundary-element model, whose K moves a grid point of contact at a time) for LM, ε² for BFGS
      (whose test on the loss's progress is not relative to the loss). BFGS with a model of finite
      precision also ends when the fit is settled: the Gauss–Newton step would lower χ² by less
      than 0.01 (the parameters within 0.1 standard errors of the optimum).
    - `starts`: explicit starts, an array of shape (n, len(params)) of physical values.
    - `prior`: what is known besides the curve: a `jaxcontact.topography.Characterisation` (its D and
      ln G with their covariance, as a Gaussian prior), or a dict by parameter of `Normal(mean, sd)`
      (a scale's sd relative to its mean in the fit: ln coordinates) or `Bounds(low, high)`. The fit
      is then the MAP estimate with the Laplace covariance `(JᵀJ/σ² + Σ_p⁻¹)⁻¹`, and
      `FitResult.information` says how much of each interval came from the curve and how much from
      the prior.
    - `noise`: σ of ln K (the curve's relative noise), which weighs the curve against a prior;
      default: the residuals' scale of the curve fitted alone. With an approach curve: σ of δ in m
      alone, or a dict `{"stiffness": σ of ln K, "approach": σ in m}`, which also weighs one
      observable against the other (default: each one's point-to-point scatter).
    - `profile`: also compute the profile likelihood of each parameter (the others re-optimised);
      where it is not parabolic, the interval comes from it (`FitResult.profiles`).

    **Returns:** a `FitResult`.
    """
    t0 = time.perf_counter()
    check_strategy("method", method, AbstractMethod, METHODS, "fitting")
    if isinstance(n_starts, bool) or not isinstance(n_starts, int) or not 1 <= n_starts <= 1024:
        raise InputError(f"n_starts = {n_starts!r} must be an integer in [1, 1024]")
    problem = Problem.of(
        loads,
        stiffness,
        scene,
        params,
        approach=approach,
        reference_load=reference_load,
        noise=noise,
        prior=prior,
        multiple=_multiple(scene),
    )
    return fit_problem(
        problem, method, n_starts=n_starts, seed=seed, max_iter=max_iter, tol=tol, starts=starts, profile=profile, t0=t0
    )


def fit_problem(
    problem: Problem,
    method: AbstractMethod = BFGS(),
    *,
    n_starts: int = 12,
    seed: int = 0,
    max_iter: int = 400,
    tol: float | None = None,
    starts=None,
    profile: bool = False,
    t0: float | None = None,
) -> FitResult:
    """`fit`'s driver: `problem` (built as `Problem.of(..., multiple=...)` with the padding `fit` uses)
    optimised from `n_starts` starts (or explicit `starts`) by `method`, then its statistics. The other
    arguments are `fit`'s; `t0` is when the caller's call began (for `FitResult.wall_time`)."""
    t0 = time.perf_counter() if t0 is None else t0
    scene = problem.scene
    fitted, gaussian, data, loads, stated = problem.params, problem.prior, problem.data, problem.loads, problem.stated
    dtype = data.loads.dtype
    if tol is None:
        floor = scene.model.precision**method.precision_power
        tol = max(method.tolerance if dtype == jnp.float64 else 1e-6, floor)
    if starts is None:
        u0s = problem.starts(n_starts, seed)
    else:
        starts = np.atleast_2d(float_array("starts", starts))
        if starts.ndim != 2 or starts.shape[1] != len(fitted) or starts.shape[0] == 0:
            names = ", ".join(p.name for p in fitted)
            raise InputError(f"starts has shape {starts.shape}: give (n, {len(fitted)}) values of {names}")
        for row in starts:
            for p, v in zip(fitted, row):
                if not p.low < v < p.high:
                    raise InputError(f"starts: {p.name} = {v:g} is outside its search range ({p.low:g}, {p.high:g})")
        u0s = np.stack([[float(p.u_from_stat(p.to_stat(v))) for p, v in zip(fitted, row)] for row in starts])
    traced_scene = problem.traced
    objective = Objective(traced_scene, fitted, data, loads.size)
    # The degrees of freedom of the noise's estimate (None: stated), for the intervals' quantiles.
    dof = None if stated else max(objective.n_points - len(fitted), 1)
    if gaussian is not None:
        # Stated noise is in the weights already: the weighted residuals are in units of σ.
        sigma = noise_scale(objective, u0s[0], 1.0 if stated else None, max_iter, tol, len(fitted))
        objective = PriorObjective(objective, gaussian, sigma)
    outcomes = [method.run(objective, u0, max_iter, tol) for u0 in u0s]
    u_all = np.stack([o.u for o in outcomes])
    losses = np.array([o.loss for o in outcomes])
    best = int(np.nanargmin(np.where(np.isfinite(losses), losses, np.inf)))
    converged = outcomes[best].converged
    stat_hat = np.array([p.stat_from_u(x) for p, x in zip(fitted, u_all[best])])
    result = statistics(traced_scene, fitted, loads, data, stat_hat)
    information = {}
    if gaussian is not None:
        result, information = with_prior(result, fitted, traced_scene, data, loads.size, stat_hat, gaussian, sigma, dof)
    profiles = {}
    if profile:
        profiles, result = profiles_of(result, fitted, traced_scene, data, loads.size, stat_hat, gaussian is None)
    success = converged and np.isfinite(losses[best]) and result.n_used > len(fitted) and result.usable
    warnings = list(result.warnings) + rival_optima(
        fitted,
        u_all,
        best,
        result.covariance,
        losses,
        objective.n_points,
        result.s2 / (1.0 if gaussian is None else sigma**2),
    )
    stall = stalled(objective, float(losses[best]), len(fitted))
    if stall:
        warnings.insert(0, stall)
        success = False
    if not converged:
        # Not only the cap: a line search can also end where the tolerance is not met.
        warnings.insert(
            0, f"the best start did not converge ({outcomes[best].iterations} iterations, at most {max_iter})"
        )
    return FitResult.of(
        result,
        fitted,
        with_stat(scene, fitted, np.asarray(stat_hat)),
        prior=gaussian,
        success=success,
        iterations=outcomes[best].iterations,
        wall_time=time.perf_counter() - t0,
        warnings=tuple(warnings),
        loss=objective.loss(u_all[best]) if gaussian is None else result.curve_loss,
        start_losses=losses,
        method=method.name,
        profiles=profiles,
        information=information,
        observables=tuple(c.name for c in data.columns),
    )


def model_stiffness(scene: jc.Scene, params, loads) -> np.ndarray:
    """The stiffness (N/m) of `scene` at `loads`, NaN where the model flags a point or K = 0, by the
    program that a fit of `params` compiles (its residuals against ln K = 0 are ln K): after
    `fit(..., scene, params)` (the fitted scene is `FitResult.scene`) nothing is traced or compiled.
    """
    fitted = resolve(params)
    loads = np.asarray(loads, dtype=float).reshape(-1)
    traced, _ = prepare(scene, loads)
    dtype = jnp.result_type(1.0)
    stat = np.array([p.to_stat(float(p.get(scene))) for p in fitted])
    stiffness = []
    chunk = POINTS_MULTIPLE if scene.model.pad_loads else loads.size
    for start in range(0, loads.size, chunk):
        part = loads[start : start + chunk]
        data, _, _ = observations(part, np.ones_like(part), None, None, None, dtype, _multiple(scene))
        e = evaluated(stat, traced, fitted, data, part.size)
        stiffness.append(np.where(e.ok, np.exp(e.r.astype(float)), np.nan))
    return np.concatenate(stiffness)
