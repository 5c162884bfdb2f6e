"""The band's power law fitted by the likelihood of its bins' means (docs/topography.md, "The band").

A bin's mean of `n` periodogram values of relative variance `s` is Gamma-distributed with shape
`k = n/s` about its expectation `μ = S(q) + N`: the power law (with its roll-off, where corrected)
plus the white floor. Fisher scoring of that likelihood (a Gamma model with a log link) needs
neither the debiasing of ln C nor the scatter for its point estimate: its score
`Σ w (C/μ - 1) ∂ln μ/∂θ` has mean zero whatever the weights `w`. The least-squares fit of the
debiased ln C depends on both: where a bin holds a few modes, the correction `ψ(k) - ln k` of a
poorly known `k` biases it, which is why a band needs `MIN_MODES` per bin. The likelihood takes
the bins of one or two modes beyond the long end as well (the measurement's longest wavelengths,
which carry the lever arm of a profile's slope; unless their own Pearson statistic says they depart
from the law: no window's test sees them), and the floor enters as the part of `μ` it is, not as a
subtraction.

The weights are those of the least-squares fit, `1/(1/k + SYSTEMATIC²)`, the systematic floor
included; the covariance is the inverse Fisher information scaled by Pearson's χ² per degree of
freedom where above 1, as for the least-squares fit.
"""

from __future__ import annotations

import numpy as np

from ._binned import ORDERS, SYSTEMATIC, Binned, rolloff_offset

MAX_STEPS = 30
Z = 3.0
TOLERANCE = 1e-10
HALVINGS = 12


def _rows(p: Binned, i: int, j: int, long_end: bool):
    """x, u, z, mean, shape of bins i..j, with the long end's few-mode bins before them where
    `long_end`, and the bins beyond the floor's margin after them where j is the last."""
    s = slice(i, j + 1)
    parts = [(p.x[s], p.u[s], p.z[s], p.mean[s], p.shape[s])]
    if long_end:
        e = p.long_end
        parts.insert(0, (e.x, e.u, e.z, e.mean, e.shape))
    if j == p.x.size - 1 and p.short_end is not None:
        e = p.short_end
        parts.append((e.x, e.u, e.z, e.mean, e.shape))
    return [np.concatenate(column) for column in zip(*parts)]


def _long_end_joins(e: Binned, mu: np.ndarray) -> bool:
    """Whether the long end's few-mode bins `e` (which no window's tests see) agree with the fitted
    law's expectations `mu` there: their Pearson statistic `Σ k (C/μ - 1)²` within `Z` of its standard
    deviations of its mean (for a Gamma mean of shape `k`, `k (C/μ - 1)²` has mean 1 and variance
    `2 + 6/k`)."""
    statistic = float(np.sum(e.shape * (e.mean / mu - 1.0) ** 2))
    return statistic - e.shape.size <= Z * float(np.sqrt(np.sum(2.0 + 6.0 / e.shape)))


def likelihood_fit(
    p: Binned, i: int, j: int, rolloff: bool, start: np.ndarray, slope: float | None = None, long_end: bool = True
):
    """Fisher scoring of the bins' Gamma likelihood over bins i..j, from `start`.

    **Arguments:** `p`, `i`, `j`, `rolloff` as `_band._fit`; `start` its least-squares coefficients
    (intercept at x = 0, then the slope unless `slope` is given, then κ where `rolloff`); `slope`,
    where D is held.

    **Returns:** `(coefficients, inverse information, χ², degrees of freedom, whether the long end's
    few-mode bins are in)` in the layout of `start`, or None where the scoring does not converge to
    finite values.
    """
    with_long_end = long_end and i == 0 and p.long_end is not None
    x, u, z, mean, shape = _rows(p, i, j, with_long_end)
    weight = 1.0 / (1.0 / shape + SYSTEMATIC**2)
    offset_x = 0.0 if slope is None else p.x0
    # Over the bins beyond the floor's margin the floor is fitted with the power law (ln N last).
    free_floor = p.floor > 0 and j == p.x.size - 1 and p.short_end is not None
    layout = len(start)
    if free_floor:
        start = np.append(start, np.log(p.floor))

    def floor_of(c):
        return np.exp(c[-1]) if free_floor else p.floor

    def log_power_law(c):
        c = c[:layout]
        value = c[0] + (c[1] * x if slope is None else slope * (x + offset_x))
        if rolloff:
            kappa = c[-1]
            value = value + kappa * u + rolloff_offset(kappa, z)
        return value

    def jacobian(c):
        """∂ ln μ / ∂c."""
        power = np.exp(log_power_law(c))
        mu = power + floor_of(c)
        columns = [np.ones_like(x)] + ([x] if slope is None else [])
        if rolloff:
            kappa = c[layout - 1]
            columns.append(u + np.sum(ORDERS[None, :] * kappa ** (ORDERS[None, :] - 1) * z, axis=-1))
        J = (power / mu)[:, None] * np.stack(columns, axis=-1)
        return np.concatenate([J, (floor_of(c) / mu)[:, None]], axis=-1) if free_floor else J, mu

    def objective(c):
        mu = np.exp(log_power_law(c)) + floor_of(c)
        return float(np.sum(weight * (np.log(mu) + mean / mu)))

    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        result = _score(start, jacobian, objective, weight, mean, layout, x.size)
    if result is None or not with_long_end:
        return None if result is None else (*result, False)
    # The long end's rows come first; the floor is nothing there beside the power law.
    mu_long = np.exp(log_power_law(result[0])[: p.long_end.x.size]) + p.floor
    if not _long_end_joins(p.long_end, mu_long):
        return likelihood_fit(p, i, j, rolloff, start[:layout], slope, long_end=False)
    return (*result, True)


def _score(start, jacobian, objective, weight, mean, layout: int, rows: int):
    """Fisher scoring with step halving on the objective; see `likelihood_fit`."""
    c = np.asarray(start, dtype=float).copy()
    current = objective(c)
    for _ in range(MAX_STEPS):
        J, mu = jacobian(c)
        information = J.T @ (weight[:, None] * J)
        try:
            step = np.linalg.solve(information, J.T @ (weight * (mean / mu - 1.0)))
        except np.linalg.LinAlgError:
            return None
        for _ in range(HALVINGS):
            trial = objective(c + step)
            if np.isfinite(trial) and trial <= current + 1e-12 * abs(current):
                break
            step = step / 2
        else:
            return None
        c, current = c + step, trial
        if np.max(np.abs(step)) < TOLERANCE:
            break
    else:
        return None
    J, mu = jacobian(c)
    information = J.T @ (weight[:, None] * J)
    if not (np.all(np.isfinite(c)) and np.all(np.isfinite(information))) or np.linalg.cond(information) > 1e12:
        return None
    dof = max(rows - c.size, 1)
    chi2 = float(np.sum(weight * (mean / mu - 1.0) ** 2))
    # The floor's block left out of the inverse: the others' covariance with it marginalised.
    return c[:layout], np.linalg.inv(information)[:layout, :layout], chi2, dof
