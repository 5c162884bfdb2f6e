"""Uncertainty at the optimum: Gauss–Newton covariance, intervals, correlations, warnings.

The covariance is `s² (JᵀJ)⁻¹` with `s² = Σr²/(N - p)`, formed in statistical coordinates (D and
ν linear; G, E, H, l_min, area logarithmic), with Student-t 95 % intervals. Points the model flags
at the optimum are left out and named.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

import jaxcontact as jc

from ._identifiability import combinations, report
from ._optimise import gauss_newton
from ._parameters import FitParameter
from ._residuals import Evaluated, evaluated
from ._result import Statistics

# A curve that fixes no combination of the parameters has measured none of them (e.g. pure noise):
# its optimum is wherever the noise put it, and the fit is not a success.
NOTHING_DETERMINED = "the curve determines no combination of the fitted parameters: the fit measured nothing"

# Optima closer than this fraction of every parameter's search range (statistical coordinates) are one.
_SAME_OPTIMUM = 1e-4


def rival_optima(params, u_all, best, covariance, losses, n_points: int, s2: float) -> list[str]:
    """Warn when another start ended at a clearly distinct optimum that fits almost as well.

    A local Gauss–Newton interval cannot describe a bimodal misfit; this model has such cases
    (e.g. a second (D, G) with a_c near the cutoff when the curve stays above F* ≈ 1e-9).
    Distinct: Mahalanobis distance > 5 under the covariance, and apart by more than `_SAME_OPTIMUM`
    of a search range; almost as well: Δχ² < 9 in the loss the starts were ranked by (`losses`,
    each start's final ½ mean r² over `n_points`, flagged points and a prior's terms included), so
    that the best start is the best by the same measure (Δχ² ≥ 0), in units of `s2`, the scatter of
    the objective's residuals at the points valid at the best optimum (the constant residuals of
    flagged points are no measure of scatter).
    """
    if not np.all(np.isfinite(covariance)):
        return []
    stats_all = np.array([[p.stat_from_u(x) for p, x in zip(params, u)] for u in u_all])
    n = max(n_points, 1)  # ½ mean r² → Σr²
    rss_best = 2.0 * n * float(losses[best])
    precision = np.linalg.pinv(covariance)
    ranges = np.ptp(np.array([p.stat_bounds for p in params]), axis=1)
    rivals = []
    for k in range(len(u_all)):
        delta = stats_all[k] - stats_all[best]
        if k == best or not np.all(np.isfinite(delta)) or float(delta @ precision @ delta) <= 25.0:
            continue
        # Distinct in practice too: a vanishing covariance (a noiseless curve) makes any two starts
        # that met at the same optimum "distinct" by Mahalanobis distance alone.
        if not np.any(np.abs(delta) > _SAME_OPTIMUM * ranges):
            continue
        rss = 2.0 * n * float(losses[k])
        # An exact fit (s2 = 0) makes any worse minimum infinitely worse, and another exact one equal.
        chi2 = (rss - rss_best) / s2 if s2 > 0 else (0.0 if rss <= rss_best else math.inf)
        if chi2 < 9.0:
            rivals.append((chi2, k))
    if not rivals:
        return []
    chi2, k = min(rivals)
    where = ", ".join(f"{p.name} = {float(p.from_stat(stats_all[k][i])):.4g}" for i, p in enumerate(params))
    return [
        f"a distinct optimum ({where}) fits almost as well (Δχ² = {chi2:.2f}): the data do not choose between "
        "them, and the intervals above describe only the best one; extend the load range (to lower F*) or "
        "add points"
    ]


def bounds_reached(params, stat, r, J) -> list[str]:
    """The warnings of the parameters whose optimum `stat` is on a search bound
    (`FitParameter.bound_reached`, with the Gauss–Newton step of the residuals `r`, Jacobian `J`)."""
    step = gauss_newton(r, J) if r.size else np.zeros(len(params))
    return [w for q, s, d in zip(params, stat, step) if (w := q.bound_reached(float(s), float(d)))]


def nothing_determined(found) -> bool:
    """Whether the curve's Fisher combinations `found` (none where no information was formed) fix none."""
    return bool(found) and not any(c.determined for c in found)


def inner_bounds(p: FitParameter):
    lo, hi = p.stat_bounds
    return lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo)


def student_t(dof: float) -> float:
    """The 97.5 % quantile of Student's t with `dof` degrees of freedom (NaN for none)."""
    return float(special.stdtrit(dof, 0.975)) if dof > 0 else math.nan  # scipy.stats costs 1 s to import


NORMAL_975 = 1.959964  # the normal distribution's 97.5 % quantile


def stderr_and_interval(q: FitParameter, stat: float, se: float, quantile: float) -> tuple[float, tuple[float, float]]:
    """A parameter's standard error and interval `stat ± quantile · se` in physical units, from its
    statistical coordinate `stat` and that coordinate's standard error `se`: a scale's (ln
    coordinates) is the delta method's value · se and exp of the ends; a linear coordinate's interval
    stays inside the parameter's domain (D in (1, 2))."""
    value = float(q.from_stat(stat))
    with np.errstate(over="ignore"):
        lo, hi = float(q.from_stat(stat - quantile * se)), float(q.from_stat(stat + quantile * se))
    if q.log:
        return value * se, (lo, hi)
    return se, (max(lo, q.low), min(hi, q.high))


def statistics(scene, params, loads, data, stat_hat) -> Statistics:
    """Gauss–Newton covariance, intervals, correlations and identifiability warnings at the optimum
    `stat_hat`, from the fit's compiled residuals (`statistics_of`).

    `loads` is the curve as given; `data` the padded `Observations`, whose padding is cut off here.
    """
    return statistics_of(evaluated(stat_hat, scene, params, data, loads.size), params, loads, data, stat_hat)


def statistics_of(e: Evaluated, params, loads, data, stat_hat) -> Statistics:
    """What `statistics` gives, from the residuals and Jacobian `e` at the optimum `stat_hat`: the one
    place where an optimum becomes covariance, intervals, identifiability and warnings (`fit` and
    `fit_batch` both end here)."""
    columns = len(data.columns)
    warnings = []
    flagged = np.flatnonzero(e.measured & ~e.ok)
    if flagged.size:
        reasons = [jc.status_message(s) if s else "K = 0: every spot plastic" for s in e.status[flagged[:5]]]
        listed = ", ".join(f"{loads[i // columns]:.4g} N ({why})" for i, why in zip(flagged[:5], reasons))
        warnings.append(
            f"{flagged.size} of {int(e.measured.sum())} points are outside the model at the optimum and were "
            f"left out of the statistics: {listed}{' …' if flagged.size > 5 else ''}"
        )
    flagged = np.unique(flagged // columns)
    J, r_used = e.J[e.used], e.r[e.used]
    n, p = J.shape
    dof = n - p
    names = [q.name for q in params]
    nan_matrix = np.full((p, p), np.nan)
    covariance, correlation, condition, information, s2 = nan_matrix, nan_matrix, math.inf, nan_matrix, math.nan
    if dof > 0:
        s2 = float(r_used @ r_used) / dof
        JTJ = J.T @ J
        information = JTJ / s2 if s2 > 0 else np.full((p, p), np.inf)
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
            warnings.append(
                "the data do not depend on "
                + ", ".join(names[i] for i in np.flatnonzero(scale == 0))
                + ": not identifiable"
            )
    else:
        warnings.append(f"{n} usable points for {p} parameters: no uncertainty can be estimated")
    t = student_t(dof)
    values, stderr, ci95 = {}, {}, {}
    for i, q in enumerate(params):
        s, se = float(stat_hat[i]), math.sqrt(covariance[i, i]) if np.isfinite(covariance[i, i]) else math.nan
        values[q.name] = float(q.from_stat(s))
        stderr[q.name], ci95[q.name] = stderr_and_interval(q, s, se, t)
    bounds = bounds_reached(params, stat_hat, r_used, J)
    warnings += bounds
    found = combinations(params, information) if np.all(np.isfinite(information)) else ()
    if any(not c.determined for c in found):
        warnings.append(report(params, found))
    if nothing_determined(found):
        warnings.append(NOTHING_DETERMINED)
    if condition > 1e8:
        warnings.append(f"the Gauss–Newton matrix is ill-conditioned (condition number {condition:.3g})")
    misfit = _misfit(loads, data, e)
    if misfit:
        warnings.append(misfit)
        # Intervals of a model that does not describe the data would look meaningful and are not.
        stderr = dict.fromkeys(stderr, math.nan)
        ci95 = dict.fromkeys(ci95, (math.nan, math.nan))
    # In each observable's own units (ln K, m): the weights undone.
    residuals = np.where(e.used, e.r, np.nan).reshape(loads.size, columns) / np.asarray(data.weights)
    residuals = residuals[:, 0] if columns == 1 else residuals
    return Statistics(
        values=values,
        stderr=stderr,
        ci95=ci95,
        covariance=covariance,
        correlation=correlation,
        condition=condition,
        warnings=tuple(warnings),
        flagged=flagged,
        residuals=residuals,
        n_used=n,
        describes_data=not misfit,
        usable=not bounds and not nothing_determined(found),
        bounds=tuple(bounds),
        identifiability=found,
        s2=s2,
        used=e.used,
        rss=float(r_used @ r_used),
    )


def _misfit(loads, data, e) -> str | None:
    """`misfit_warning` of the first observable whose residuals exceed its data's own scatter (in ln K;
    the approach relative to its rms)."""
    columns = len(data.columns)
    targets = np.asarray(data.targets)[: loads.size]
    used = e.used.reshape(-1, columns)
    r = e.r.reshape(-1, columns) / np.asarray(data.weights)
    for k, column in enumerate(data.columns):
        keep = used[:, k]
        y, rk = targets[keep, k], r[keep, k]
        scale = column.scale(y)  # relative to the curve's size, as ln K's residuals are
        y, rk = y / scale, rk / scale
        found = misfit_warning(np.log(loads[keep]), y, rk, column.misfit_unit)
        if found:
            return found
    return None


# Below this rms (ln units, ~2 %) a misfit is too small to call the model wrong, whatever the data's scatter.
_NEGLIGIBLE_MISFIT = 0.02


def point_scatter(x, y) -> float:
    """The noise σ of `y` from the data alone: each point's deviation from the straight line
    through its two neighbours in `x` (a smooth curve is locally straight), scaled by what that
    deviation's variance is for independent noise, robustly (median, not mean)."""
    order = np.argsort(x)
    x, y = np.asarray(x)[order], np.asarray(y)[order]
    x0, x1, x2, y0, y1, y2 = x[:-2], x[1:-1], x[2:], y[:-2], y[1:-1], y[2:]
    span = x2 - x0
    keep = span > 0
    if not keep.any():
        return math.nan
    w0, w2 = (x2 - x1)[keep] / span[keep], (x1 - x0)[keep] / span[keep]
    d = y1[keep] - (w0 * y0[keep] + w2 * y2[keep])
    # For independent noise of variance σ², d has variance σ² (1 + w0² + w2²); the median of χ²₁ is 0.4549.
    return float(np.sqrt(np.median(d * d / (1 + w0 * w0 + w2 * w2)) / 0.4549))


def misfit_warning(log_loads, log_stiffness, residuals, observed: str = "in K") -> str | None:
    """A warning when the fit misses the data by far more than the data scatter about themselves:
    then the model does not describe them (wrong units, another model, another effect)."""
    if residuals.size < 3:
        return None
    rms = float(np.sqrt(np.mean(residuals * residuals)))
    scatter = point_scatter(log_loads, log_stiffness)
    # A few points estimate the scatter poorly: the ratio must also exceed what chance gives one curve
    # in a thousand (an F quantile; 3 is the larger from ~30 points on).
    n = residuals.size
    factor = max(3.0, math.sqrt(float(special.fdtri(n, max(n - 2, 1), 0.999))))
    if rms <= _NEGLIGIBLE_MISFIT or not (rms > factor * scatter):
        return None
    return (
        f"the rms misfit ({100 * rms:.3g} % {observed}) is "
        f"{f'{rms / scatter:.3g}x' if scatter > 0 else 'far above'} the "
        "data's own point-to-point scatter "
        f"({100 * scatter:.3g} %): the model does not describe these data (loads or stiffness in other units? "
        "another model? an effect the model lacks?); the values and intervals above are not to be trusted"
    )
