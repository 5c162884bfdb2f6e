"""What `fit_batch` returns, per curve: the statistics `fit` gives of one curve (`statistics_of`, the
one place where an optimum becomes intervals and warnings), laid out with a leading curves axis."""

from __future__ import annotations

import dataclasses

import numpy as np

from ._optimise import half_mean_square
from ._parameters import with_stat
from ._prior import with_prior_of
from ._residuals import Evaluated
from ._result import FitResult
from ._statistics import rival_optima, statistics_of


@dataclasses.dataclass(frozen=True)
class BatchResult:
    """Per curve (leading axis of every array): `values`, `stderr`, `ci95` (dicts by name of arrays;
    `ci95[name]` has shape (curves, 2)), `correlation` (curves, p, p), `loss` (½ mean r²), `iterations`,
    `success` (converged, finite, enough valid points, no parameter on a search bound, and some
    combination of the parameters determined: a curve of pure noise is not a success), `flagged`
    (valid-point mask is its negation: shape (curves, points)), `determined` (curves, p: whether each
    Fisher combination is determined), `warnings` (a tuple of strings per curve), `wall_time` (s,
    compilation included), `compile_time` (0 where a batch of the same shape was compiled before in
    this process); with a prior, `information` (per curve, `fit`'s report by parameter of where its
    interval's information came from) and `prior` (where the prior came from); `fits` (per curve, the
    `FitResult` that `fit` returns, built from the same statistics: its `summary()`, its fitted
    `scene`; None for a curve that was not fitted)."""

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
    information: tuple = ()
    prior: str | None = None
    fits: tuple = ()


def batch_statistics(
    scene, fitted, loads, data, outcome, max_iter, wall_time, compile_time, gaussian=None, sigmas=None, stated=False
):
    """Per curve (`data`: each one's `Observations`), `statistics_of` at its optimum `u` (optimiser
    coordinates) from the program's residuals `r`, valid mask `ok`, statuses and Jacobian `J` (each
    (curves, points, ...)), with the solver's step count `k`, whether it `converged`, and the loss: the
    values, intervals, correlations, identifiability and warnings `fit` gives; plus the batch's own
    note of a curve whose fit did not converge. `outcome` is the program's
    `(u, loss, k, converged, r, ok, status, J, us, losses)`,
    the last two every start's end and loss (½ mean r² over every entry, measured or not). With a
    prior (`gaussian`), each curve's intervals are the Laplace posterior's at its noise `sigmas[c]`
    (`with_prior_of`; `stated`: whether the noise was stated, else each curve's σ was estimated from
    its residuals fitted alone), as `fit`'s."""
    u, loss, k, converged, r, ok, status, J, us, losses = outcome
    p, curves = len(fitted), u.shape[0]
    names = [q.name for q in fitted]
    values = {n: np.full(curves, np.nan) for n in names}
    stderr = {n: np.full(curves, np.nan) for n in names}
    ci95 = {n: np.full((curves, 2), np.nan) for n in names}
    correlation = np.full((curves, p, p), np.nan)
    determined = np.zeros((curves, p), bool)
    success = np.zeros(curves, bool)
    warnings, information, fits = [], [], []
    for c in range(curves):
        stat = np.array([q.stat_from_u(x) for q, x in zip(fitted, u[c])])
        e = Evaluated(
            r[c].reshape(-1),
            ok[c].reshape(-1),
            status[c].reshape(-1),
            J[c].reshape(-1, p),
            data[c].measured.reshape(-1),
        )
        result = statistics_of(e, fitted, loads[c], data[c], stat)
        sigma = 1.0
        if gaussian is not None:
            sigma = float(sigmas[c])
            dof = None if stated else max(int(e.measured.sum()) - p, 1)
            result, found = with_prior_of(result, e, fitted, stat, gaussian, sigma, dof)
            information.append(found)
        for n in names:
            values[n][c], stderr[n][c], ci95[n][c] = result.values[n], result.stderr[n], result.ci95[n]
        correlation[c] = result.correlation
        determined[c] = [f.determined for f in result.identifiability] or False
        success[c] = bool(converged[c]) and np.isfinite(loss[c]) and result.usable and result.n_used > p
        notes = [] if converged[c] else [f"did not converge in {max_iter} Levenberg–Marquardt steps"]
        best = int(np.nanargmin(np.where(np.isfinite(losses[c]), losses[c], np.inf)))
        rivals = rival_optima(fitted, us[c], best, result.covariance, losses[c], r[c].size, result.s2 / sigma**2)
        warnings.append(tuple(notes + list(result.warnings) + rivals))
        # As `fit` reports it: ½ mean square over the measured values (unmeasured entries are 0); with a
        # prior, of the curve alone.
        curve_loss = half_mean_square(e.r, int(e.measured.sum())) if gaussian is None else result.curve_loss
        fits.append(
            FitResult.of(
                result,
                fitted,
                with_stat(scene, fitted, stat),
                prior=gaussian,
                success=bool(success[c]),
                iterations=int(k[c]),
                wall_time=wall_time,
                warnings=warnings[-1],
                loss=curve_loss,
                start_losses=np.asarray(losses[c], dtype=float),
                method="Levenberg–Marquardt (optimistix)",
                information=information[-1] if gaussian is not None else {},
                observables=tuple(col.name for col in data[c].columns),
            )
        )
    return BatchResult(
        params=tuple(names),
        values=values,
        stderr=stderr,
        ci95=ci95,
        correlation=correlation,
        loss=np.asarray(loss, dtype=float),
        iterations=np.asarray(k),
        success=success,
        flagged=~ok.reshape(curves, -1),
        determined=determined,
        warnings=tuple(warnings),
        wall_time=wall_time,
        compile_time=compile_time,
        information=tuple(information),
        prior=None if gaussian is None else gaussian.source,
        fits=tuple(fits),
    )


def without(result: BatchResult, bad: dict[int, str]) -> BatchResult:
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
    fits = tuple(None if c in bad else f for c, f in enumerate(result.fits))
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
        fits=fits,
    )
