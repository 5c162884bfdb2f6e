"""Uncertainty at the optimum: Gauss–Newton covariance, intervals, correlations, warnings.

The covariance is `s² (JᵀJ)⁻¹` with `s² = Σr²/(N - p)`, formed in statistical coordinates (D and
ν linear; G, E, H, l_min, area logarithmic), with Student-t 95 % intervals. Points the model flags
at the optimum are left out and named.
"""

from __future__ import annotations

import math

import jax
import numpy as np
from scipy import stats

import jaxcontact as jc

from .parameters import FitParameter
from .residuals import residuals_and_jacobian, stat_from_u


def rival_optima(params, u_all, losses, best, n_points, result) -> list[str]:
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
    stats_all = np.asarray(jax.vmap(lambda u: stat_from_u(params, u))(u_all))
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
    return [
        f"a distinct optimum ({where}) fits almost as well (Δχ² = {chi2:.2f}): the data do not choose between "
        "them, and the intervals above describe only the best one; extend the load range (to lower F*) or "
        "add points"
    ]


def inner_bounds(p: FitParameter):
    lo, hi = p.stat_bounds
    return lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo)


def statistics(scene, params, loads, data, stat_hat, u_hat) -> dict:
    """Gauss–Newton covariance, intervals, correlations and identifiability warnings at the optimum.

    `loads` is the curve as given; `data` is `_padded_curve`'s, whose padding is cut off here.
    """
    padded_loads, log_stiffness, _ = data
    r, ok, status, J = (
        np.asarray(x)[: loads.size]
        for x in residuals_and_jacobian(stat_hat, scene, params, padded_loads, log_stiffness)
    )
    warnings = []
    flagged = np.flatnonzero(~ok)
    if flagged.size:
        status = status[flagged]
        listed = ", ".join(f"{loads[i]:.4g} N ({jc.status_message(s)})" for i, s in zip(flagged[:5], status[:5]))
        warnings.append(
            f"{flagged.size} of {loads.size} points are outside the model at the optimum and were "
            f"left out of the statistics: {listed}{' …' if flagged.size > 5 else ''}"
        )
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
            warnings.append(
                "the data do not depend on "
                + ", ".join(names[i] for i in np.flatnonzero(scale == 0))
                + ": not identifiable"
            )
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
                warnings.append(
                    f"{names[i]} and {names[j]} are strongly correlated (r = {correlation[i, j]:+.4f}): "
                    "poorly identified separately"
                )
    if condition > 1e8:
        warnings.append(f"the Gauss–Newton matrix is ill-conditioned (condition number {condition:.3g})")
    residuals = np.where(ok, r, np.nan)
    return dict(
        values=values,
        stderr=stderr,
        ci95=ci95,
        covariance=covariance,
        correlation=correlation,
        condition=condition,
        warnings=warnings,
        flagged=flagged,
        residuals=residuals,
        n_used=n,
    )
