"""Many curves at once: one compiled, `vmap`ped fit per curve (and start) with optimistix's
Levenberg–Marquardt on the model's exact Jacobian (docs/fitting.md, "Many curves at once").

Each curve is fitted as `fitting.fit` fits one: ln-stiffness residuals, the bounded
reparameterisation `s = low + (high − low)·sigmoid(u)`, several starts (a Latin hypercube, the
scene's values one of them), the best kept; then, per curve, the statistics `fit` gives
(`_batch_result`). Each step of each start evaluates the model once, with its forward-mode Jacobian
over the few parameters, and the program holds the model once. The whole batch is one XLA program: on an
accelerator the curves run in parallel.
"""

from __future__ import annotations

import functools
import time

import jax
import jax.numpy as jnp
import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.numerics import float_array

from ._batch_program import fit_curves
from ._batch_result import BatchResult, batch_statistics, without
from ._compiled import compiled
from ._observables import Approach, Stiffness
from ._parameters import resolve
from ._prior import prior_arrays, residual_scale, resolve_prior
from ._problem import Problem


def fit_batch(
    loads,
    stiffness,
    scene: jc.Scene,
    params=("D", "G"),
    *,
    approach=None,
    reference_load=None,
    noise: float | dict[str, float] | None = None,
    prior=None,
    n_starts: int = 4,
    seed: int = 0,
    max_iter: int = 100,
    tol: float = 1e-10,
    chunk: int = 32,
) -> BatchResult:
    """Fit `params` to many curves at once, one compiled program for all of them: each curve as `fit`
    fits it (its observables, their weights and statistics), with optimistix's Levenberg–Marquardt.

    **Arguments:** `loads` (N, shape (curves, points)); `stiffness` (N/m, the same shape; NaN where only
    the approach was measured; `None` with `approach` alone); `approach` (m, δ(F) − δ(F0), the same
    shape, NaN where not measured); `reference_load` (the preload F0, N: one for all curves or one per
    curve; default each curve's smallest load); `noise` (as `fit`'s: σ of ln K, or a dict by observable);
    `prior` (as `fit`'s, the same for every curve: the MAP estimate and its Laplace covariance per
    curve, each curve weighed against it by its own noise, stated or its residuals' scale fitted alone);
    `scene` (what is not fitted, shared by the curves, and one start); `params`; `n_starts` (per curve);
    `seed` (of the Latin-hypercube starts); `max_iter`, `tol` (the cap on Levenberg–Marquardt steps, and
    the tolerance, relative and absolute, on an accepted step's change of the parameters in optimiser
    coordinates and of the residuals; a start that uses up its steps has converged all the same where the
    Gauss–Newton step from its end would gain less than 1e-6 in χ²); `chunk` (curves per call of the compiled program:
    a `vmap`ped loop runs until its slowest lane ends, so one start that needs many steps holds its
    chunk, not the batch; on an accelerator a larger chunk fills it better).

    **Returns:** a `BatchResult`. A curve with a value outside its valid range is not fitted (NaN values,
    `success` False, a warning naming the curve and the point); the others are.
    """
    t0 = time.perf_counter()
    # An error in the parameters or the prior is the batch's, not a curve's.
    p = len(resolve_prior(prior, resolve(params))[1])
    if isinstance(n_starts, bool) or not isinstance(n_starts, int) or not 1 <= n_starts <= 64:
        raise InputError(f"n_starts = {n_starts!r} must be an integer in [1, 64]")
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise InputError(f"chunk = {chunk!r} must be a number of curves >= 1")
    observed = dict(approach=approach, reference_load=reference_load, noise=noise, prior=prior)
    loads, problems, bad = _curves(loads, stiffness, scene, params, p, observed)
    first = problems[0]
    fitted, gaussian, traced, data = first.params, first.prior, first.traced, [p.data for p in problems]
    u0s = jnp.asarray(first.starts(n_starts, seed), data[0].loads.dtype)
    batch = functools.partial(_run, traced, fitted, data, u0s, max_iter, tol, chunk)
    sigmas = np.ones(len(data))
    compile_time = 0.0
    if gaussian is not None and not first.stated:
        # Each curve's noise in ln K: its residuals' scale fitted alone (`fit`'s `noise_scale`).
        alone, compile_time = batch(sigmas, None)
        sigmas = np.array(
            [residual_scale(r.reshape(-1), int(d.measured.sum()), len(fitted)) for r, d in zip(alone[4], data)]
        )
    outcome, seconds = batch(sigmas, gaussian)
    wall_time = time.perf_counter() - t0
    result = batch_statistics(
        scene, fitted, loads, data, outcome, max_iter, wall_time, compile_time + seconds, gaussian, sigmas, first.stated
    )
    return without(result, bad)


def _run(traced, fitted, data, u0s, max_iter, tol, chunk, sigmas, gaussian):
    """The compiled program over every curve, `chunk` at a time: its outputs (curves first), and the
    seconds spent compiling it (0 where a batch of its shape was compiled before in this process)."""
    dtype = u0s.dtype
    prior, index, kind = prior_arrays(gaussian, dtype)
    curves = len(data)
    size = min(chunk, curves)
    # The last chunk is filled with copies of the first curve (cut off after): one compiled shape.
    stacked, sigmas = data + [data[0]] * (-curves % size), np.concatenate([sigmas, np.ones(-curves % size)])
    outputs, compile_time = [], 0.0
    for start in range(0, len(stacked), size):
        part = jax.tree.map(lambda *x: jnp.stack(x), *stacked[start : start + size])
        sigma = jnp.asarray(sigmas[start : start + size], dtype)
        run, dynamic, seconds = compiled(
            fit_curves, traced, part, sigma, prior, u0s, fitted, max_iter, tol, index, kind
        )
        compile_time += seconds
        outputs.append([np.asarray(x) for x in run(dynamic)])
    return tuple(np.concatenate(parts)[:curves] for parts in zip(*outputs)), compile_time


def _curves(loads, stiffness, scene, params, p: int, observed: dict):
    """`(loads, problems, bad)`: the loads (curves, points), each curve's `Problem` (a good curve's
    standing in for a curve that cannot be fitted: one compiled shape), and by curve why it cannot.
    `p` parameters are fitted; `observed`: the approach (curves, points), reference load (one, or one
    per curve), noise and prior."""
    loads = np.atleast_2d(float_array("loads", loads))
    if loads.ndim != 2 or loads.shape[0] == 0:
        raise InputError(f"loads has shape {loads.shape}: give (curves, points), at least one curve")
    if loads.shape[1] <= p:
        raise InputError(f"{loads.shape[1]} points per curve cannot determine {p} parameters")
    given = {k: v for k, v in (("stiffness", stiffness), ("approach", observed["approach"])) if v is not None}
    if not given:
        raise InputError("stiffness = None and approach = None: give at least one measured curve per load")
    given = {k: np.atleast_2d(float_array(k, v)) for k, v in given.items()}
    for name, values in given.items():
        if values.shape != loads.shape:
            raise InputError(f"loads {loads.shape} and {name} {values.shape} differ in shape (curves, points)")
    reference = observed["reference_load"]
    references = np.broadcast_to(
        np.nan if reference is None else float_array("reference_load", reference), loads.shape[:1]
    )
    bad, problems = _bad_points(loads, given), {}
    for c in range(loads.shape[0]):
        if c in bad:
            continue
        try:
            problems[c] = Problem.of(
                loads[c],
                given["stiffness"][c] if "stiffness" in given else None,
                scene,
                params,
                approach=given["approach"][c] if "approach" in given else None,
                reference_load=None if np.isnan(references[c]) else float(references[c]),
                noise=observed["noise"],
                prior=observed["prior"],
            )
        except InputError as exc:
            bad[c] = f"curve {c}: {exc}"
    if not problems:
        raise InputError(f"no curve can be fitted: {bad[0]}")
    good = next(iter(problems.values()))
    return loads, [problems.get(c, good) for c in range(loads.shape[0])], bad


def _bad_points(loads, given: dict) -> dict[int, str]:
    """By curve, the first point whose load, stiffness or approach is outside its valid range, described
    (a stiffness may be NaN where an approach is given; an approach NaN where not measured)."""
    checks = {
        "loads": lambda v: np.isfinite(v) & (v > 0),
        "stiffness": lambda v: Stiffness().valid(v) & (np.isfinite(v) | ("approach" in given)),
        "approach": Approach().valid,
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
