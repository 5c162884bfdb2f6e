"""A white noise floor at the short end of a measured spectrum (docs/topography.md, "The band")."""

from __future__ import annotations

import numpy as np
from scipy import optimize

# The floor is sought in the spectrum's top decade and a half (then three), under a power law
# steeper than D = 2's slope (-2 areal, -1 profile) less twice `FLOOR_MARGIN_SLOPE` of `_band`; a
# top that is flatter than D = 2's slope plus it is all floor.
FLOOR_DECADES = 1.5
# Far below the spectrum's top, a "floor" is the FFT's round-off under a steep roll-off.
ROUND_OFF = 1e-16
# A floor must lower χ² by more than this (3 standard errors) against a plain power law.
SIGNIFICANT = 9.0


def noise_floor(q, C, modes, scatter, flattest: float) -> float:
    """The white noise level of the spectrum's short end, or 0 where there is none.

    `C = A q^b + N` is fitted over the top `FLOOR_DECADES` (log residuals, weighted by the bins' own
    scatter), and over twice that where the floor covers the whole top; a floor is kept when it
    lowers χ² by more than `Z²` against `C = A q^b` and lies below the bins (a spectrum that flattens
    at its short end, where a roll-off would steepen it). A top octave that is flat already (slope
    above `flattest`) is the floor: its mean."""
    for decades in (FLOOR_DECADES, 2 * FLOOR_DECADES):
        floor = fitted_floor(q, C, modes, scatter, decades, flattest)
        if floor > ROUND_OFF * C.max():
            return floor
    top = q >= q[-1] / 2
    if top.sum() >= 3 and np.polyfit(np.log(q[top]), np.log(C[top]), 1)[0] > flattest:
        return float(np.average(C[top], weights=modes[top]))
    return 0.0


def fitted_floor(q, C, modes, scatter, decades: float, flattest: float) -> float:
    top = q >= q[-1] / 10**decades
    if top.sum() < 6:
        return 0.0
    x, y, w = np.log(q[top]), np.log(C[top]), np.sqrt(modes[top] / scatter[top])
    line = np.polyfit(x, y, 1, w=w)
    chi2_line = float(np.sum((w * (y - np.polyval(line, x))) ** 2))

    def residuals(theta):
        return w * (np.logaddexp(theta[0] + theta[1] * x, theta[2]) - y)

    # Started from a floor at the smallest bin and the power law of the lower half of the range.
    lower = x <= np.median(x)
    start = np.polyfit(x[lower], y[lower], 1, w=w[lower])
    fit = optimize.least_squares(residuals, [start[1], start[0], float(y.min())], method="lm")
    slope, log_floor = fit.x[1], fit.x[2]
    if not (fit.success and chi2_line - 2 * fit.cost > SIGNIFICANT and slope < flattest - 0.4 and log_floor < y.max()):
        return 0.0
    return float(np.exp(log_floor))
