"""Where a measured spectrum is a power law: the band a fit may use, found from the data.

The criterion (docs/topography.md, "The band"): among all windows of the binned spectrum
(`_whole.Spectrum`) spanning at least a factor `MIN_RATIO` in q, with at least `MIN_MODES`
independent modes in every bin, take the *widest* in log q in which

1. a straight line in log-log fits within the bins' own scatter (χ² ≤ ν + 3√(2ν), the variance of
   ln C per bin being the periodogram's scatter over its modes plus `SYSTEMATIC`²), and
2. a parabola does not improve on it (its quadratic coefficient within 3 standard errors of 0), and
3. the slope gives 1 < D < 2.

Instruments add three artefacts that the window's ends must exclude. A white **noise floor** (a
spectrum that flattens at its short end, its slope `FLOOR_MARGIN_SLOPE` above that of D = 2, shallower than any
self-affine one) is estimated from the top octave and subtracted; bins within 3× of it are left
out. A **transfer function** (an optical profiler's lateral resolution, a tip) rolls the spectrum
off gradually, which a straight line absorbs by tilting: a window may therefore carry a Gaussian
roll-off `exp(-κ q²)` as a third term where that term is significant (3 standard errors) and
corrects by at most `ROLLOFF_CAP` in ln C; the better determined of the widest straight and corrected
windows is chosen, unless the straight one is tilted by the roll-off (`_tilted`). A **sharp cutoff**
(a low-pass filter) fails test 1 at once. The tip's reliability cutoff, where known, bounds the band
from the start.

The slope's and intercept's covariance is the weighted least-squares one, scaled by the reduced χ²
where above 1, plus the band's own systematic: the change of (slope, intercept) when the short end
moves in by a factor 2 (the end nearest the artefacts).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import special

from ._floor import noise_floor
from ._whole import Spectrum

MIN_MODES = 3
MIN_RATIO = 4.0
Z = 3.0
# No measured spectrum is a power law to better than about 1 % per bin.
SYSTEMATIC = 0.01
# Nor is an instrument's height scale known to better than about 1 %: 2 % in C, the same at every q.
CALIBRATION = 0.02
FLOOR_MARGIN_SLOPE = 0.2
FLOOR_MARGIN = 2.0
ROLLOFF_CAP = 4.0
TRIM = math.log(2.0)


@dataclasses.dataclass(frozen=True)
class PowerLaw:
    """A power law `C = exp(intercept) q^slope` fitted over `band` (q_low, q_high in rad/m).

    **Fields:** `slope`, `intercept` (ln C at q = 1 rad/m), `covariance` of (slope, intercept);
    `band`; `rolloff` (σ of the corrected roll-off `exp(-(qσ)²)` in m, or None); `floor` (the
    subtracted white noise level of C, or 0); `ends` (why the long and the short end lie where they
    do); `bins` (in the band); `points` (the band's bins as q, debiased ln C with the floor and the
    roll-off taken out, and weight: what a fit over several measurements joins).
    """

    slope: float
    intercept: float
    covariance: np.ndarray
    band: tuple[float, float]
    rolloff: float | None
    floor: float
    ends: tuple[str, str]
    bins: int
    points: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None


@dataclasses.dataclass(frozen=True)
class _Prepared:
    x: np.ndarray  # ln q, centred
    x0: float
    y: np.ndarray  # ln C, debiased
    w: np.ndarray  # 1 / variance
    u: np.ndarray  # -(q / q_top)²
    q: np.ndarray
    floor: float
    lost_long: bool  # bins dropped at the long end for too few modes
    short_cause: str


def _prepare(spectrum: Spectrum, q_max: float | None) -> _Prepared | None:
    keep = (spectrum.modes >= MIN_MODES) & (spectrum.C > 0)
    short_cause = "the grid's shortest wavelength (two spacings)"
    if q_max is not None and np.any(spectrum.q > q_max):
        keep &= spectrum.q <= q_max
        short_cause = "the tip's reliability cutoff"
    q, C, modes, scatter = spectrum.q[keep], spectrum.C[keep], spectrum.modes[keep], spectrum.scatter[keep]
    q2 = (spectrum.q**2 if spectrum.q_squared is None else spectrum.q_squared)[keep]
    if q.size < 5:
        return None
    floor = noise_floor(q, C, modes, scatter, float(spectrum.slope_of(2.0)) + FLOOR_MARGIN_SLOPE)
    if floor > 0:
        above = C > FLOOR_MARGIN * floor
        q, C, modes, scatter, q2 = q[above], C[above] - floor, modes[above], scatter[above], q2[above]
        short_cause = f"the noise floor (subtracted; within {FLOOR_MARGIN:g}× of it beyond)"
        if q.size < 5:
            return None
    lost_long = bool(spectrum.modes[0] < MIN_MODES)
    return _prepared(q, C, modes, scatter, floor, lost_long, short_cause, q2)


def _prepared(q, C, modes, scatter, floor=0.0, lost_long=False, short_cause="", q_squared=None) -> _Prepared:
    """`C` (less `floor`, already) in log-log with its per-bin bias correction and weight."""
    # A bin's mean of `modes` periodogram values of relative variance `scatter` is Gamma-distributed
    # with shape k = modes / scatter: E ln(mean/C) = ψ(k) - ln k, var ln(mean) = ψ'(k).
    k = modes / scatter
    # The floor's subtraction leaves the bin's scatter: relative to what is left, it grows by (C+N)/C.
    variance = special.polygamma(1, k) * ((C + floor) / C) ** 2
    x = np.log(q)
    return _Prepared(
        x=x - x.mean(),
        x0=float(x.mean()),
        y=np.log(C) - (special.digamma(k) - np.log(k)),
        w=1.0 / (variance + SYSTEMATIC**2),
        u=-(q * q if q_squared is None else q_squared) / q[-1] ** 2,
        q=q,
        floor=floor,
        lost_long=lost_long,
        short_cause=short_cause,
    )


def _all_windows(p: _Prepared, columns):
    """Weighted least squares of `p.y` on `columns` over every window [i, j] (j ≥ i + 4), by cumulative
    moments: coefficients, their unscaled covariance, χ² and degrees of freedom, as B × B arrays."""
    X = np.stack(columns, axis=-1)
    k = X.shape[1]
    cumulative = lambda a: np.concatenate([np.zeros((1,) + a.shape[1:]), np.cumsum(a, axis=0)])  # noqa: E731
    XX = cumulative(p.w[:, None, None] * X[:, :, None] * X[:, None, :])
    XY = cumulative(p.w[:, None] * X * p.y[:, None])
    YY = cumulative(p.w * p.y * p.y)
    B = p.x.size
    long_end, short_end = np.meshgrid(np.arange(B), np.arange(B), indexing="ij")
    valid = short_end - long_end >= 4
    Ic, Jc = np.where(valid, long_end, 0), np.where(valid, short_end, 4)
    A = XX[Jc + 1] - XX[Ic] + (~valid)[..., None, None] * np.eye(k)
    r = XY[Jc + 1] - XY[Ic]
    inverse = np.linalg.inv(A)
    coefficients = np.einsum("...ij,...j->...i", inverse, r)
    chi2 = YY[Jc + 1] - YY[Ic] - np.einsum("...i,...i->...", coefficients, r)
    dof = np.maximum(Jc - Ic + 1 - k, 1)
    return coefficients, inverse, np.maximum(chi2, 0.0), dof, valid


def _widest(p: _Prepared, ok):
    if not ok.any():
        return None
    span = np.where(ok, p.x[None, :] - p.x[:, None], -1.0)
    return np.unravel_index(int(np.argmax(span)), span.shape)


def _windows(p: _Prepared, D_of):
    one = np.ones_like(p.x)
    line, line_inv, line_chi2, line_dof, valid = _all_windows(p, [one, p.x])
    quad, quad_inv, quad_chi2, quad_dof, _ = _all_windows(p, [one, p.x, p.x * p.x])
    roll, roll_inv, roll_chi2, roll_dof, _ = _all_windows(p, [one, p.x, p.u])
    J = np.arange(p.x.size)[None, :]
    wide = valid & (p.x[None, :] - p.x[:, None] >= math.log(MIN_RATIO))
    passes = lambda chi2, dof: chi2 <= dof + Z * np.sqrt(2 * dof)  # noqa: E731
    straight = (
        wide
        & passes(line_chi2, line_dof)
        & (np.abs(quad[..., 2]) <= Z * np.sqrt(quad_inv[..., 2, 2] * np.maximum(1, quad_chi2 / quad_dof)))
        & (D_of(line[..., 1]) > 1)
        & (D_of(line[..., 1]) < 2)
    )
    kappa_z = roll[..., 2] / np.sqrt(roll_inv[..., 2, 2] * np.maximum(1, roll_chi2 / roll_dof))
    rolled = (
        wide
        & passes(roll_chi2, roll_dof)
        & (kappa_z > Z)
        & (roll[..., 2] * -p.u[J] <= ROLLOFF_CAP)
        & (D_of(roll[..., 1]) > 1)
        & (D_of(roll[..., 1]) < 2)
    )
    return straight, rolled, line_chi2 / line_dof, D_of(line[..., 1]), wide


def _fit(p: _Prepared, i: int, j: int, rolloff: bool, slope: float | None = None):
    """(slope, intercept at q = 1), their covariance, and κ, over bins i..j; with `slope` given, the
    intercept (and κ) alone."""
    s = slice(i, j + 1)
    y = p.y[s] if slope is None else p.y[s] - slope * (p.x[s] + p.x0)
    columns = [np.ones(j + 1 - i)] + ([p.x[s]] if slope is None else []) + ([p.u[s]] if rolloff else [])
    X = np.stack(columns, axis=-1)
    w = p.w[s]
    inverse = np.linalg.inv(X.T @ (w[:, None] * X))
    c = inverse @ (X.T @ (w * y))
    dof = max(X.shape[0] - X.shape[1], 1)
    chi2 = float(np.sum(w * (y - X @ c) ** 2))
    to_physical = np.zeros((2, X.shape[1]))
    if slope is None:
        to_physical[0, 1] = 1.0
        to_physical[1, 0], to_physical[1, 1] = 1.0, -p.x0  # intercept at ln q = 0
        theta = to_physical @ c
    else:
        to_physical[1, 0] = 1.0
        theta = np.array([slope, c[0]])
    covariance = to_physical @ inverse @ to_physical.T * max(1.0, chi2 / dof) + np.diag([0.0, CALIBRATION**2])
    return theta, covariance, (float(c[-1]) if rolloff else 0.0)


def _with_systematics(p: _Prepared, i: int, j: int, rolloff: bool, slope):
    """`_fit` over bins i..j, its covariance with the band's systematic: the change when either end
    moves in by a factor 2."""
    theta, covariance, kappa = _fit(p, i, j, rolloff, slope)
    shorter = int(np.searchsorted(p.x, p.x[j] - TRIM, side="right")) - 1
    longer = int(np.searchsorted(p.x, p.x[i] + TRIM, side="left"))
    for start, stop in ((i, shorter), (longer, j)):
        if stop - start >= 4:
            moved = _fit(p, start, stop, rolloff, slope)[0] - theta
            covariance = covariance + np.outer(moved, moved)
    return theta, covariance, kappa


def _tilted(p: _Prepared, straight, corrected) -> bool:
    """Whether the straight fit (`((theta, covariance, kappa), (i, j), rolloff)`, as `corrected`) is a
    line tilted by the corrected fit's roll-off, which its own tests cannot see where the roll-off and
    the slope are nearly collinear: inside the corrected window, lowered at its short end by more
    than `Z · SYSTEMATIC` in ln C, its slope off by more than the two's combined standard error."""
    ((theta, covariance, _), (i, j), _), ((theta_c, covariance_c, kappa), (ci, cj), _) = straight, corrected
    within = ci <= i and cj >= j and kappa * -p.u[j] > Z * SYSTEMATIC
    return within and abs(theta[0] - theta_c[0]) > math.sqrt(covariance[0, 0] + covariance_c[0, 0])


def select_band(
    spectrum: Spectrum, q_max: float | None = None, slope: float | None = None
) -> PowerLaw | tuple[float, float] | None:
    """The widest power-law band of `spectrum` (the module's criterion), bounded above by `q_max`;
    with `slope` given, the power law's intercept alone over that band (D held).

    **Returns:** a `PowerLaw`; or, where no window passes, the wavelengths (short, long) in m of the
    window that comes closest (the best straight fit with 1 < D < 2 over a factor 4), to suggest;
    or None when no stretch of the spectrum has a self-affine slope.
    """
    p = _prepare(spectrum, q_max)
    if p is None:
        return None
    straight, rolled, reduced, D, wide = _windows(p, spectrum.D_of)
    # Beside a subtracted floor a roll-off is not sought: the subtraction's own scatter can mimic one.
    options = [(w, r) for w, r in ((_widest(p, straight), False), (_widest(p, rolled), True)) if w is not None]
    options = [(w, r) for w, r in options if not (r and p.floor > 0)]
    if not options:
        candidates = wide & (D > 1) & (D < 2)
        if not candidates.any():
            return None
        i, j = np.unravel_index(int(np.argmin(np.where(candidates, reduced, np.inf))), reduced.shape)
        return 2 * np.pi / p.q[j], 2 * np.pi / p.q[i]
    # The better determined, the band's systematic included (a line tilted to absorb a roll-off moves
    # when the short end does), unless the straight one is tilted where it does not move.
    fits = [(_with_systematics(p, int(w[0]), int(w[1]), r, slope), (int(w[0]), int(w[1])), r) for w, r in options]
    chosen = min(fits, key=lambda f: (f[0][1][0, 0], f[0][1][1, 1]))
    if fits[-1][2] and not chosen[2] and _tilted(p, chosen, fits[-1]):
        chosen = fits[-1]
    (theta, covariance, kappa), (i, j), rolloff = chosen
    short = (
        p.short_cause
        if j == p.x.size - 1
        else "beyond it the spectrum rolls off faster than the corrected Gaussian transfer function"
        if rolloff
        else "beyond it the spectrum departs from the power law (a roll-off, filter or noise)"
    )
    long = "beyond it the spectrum departs from the power law"
    if i == 0:
        long = (
            f"fewer than {MIN_MODES} independent modes per bin beyond it"
            if p.lost_long
            else "the measurement's longest wavelength"
        )
    return PowerLaw(
        slope=float(theta[0]),
        intercept=float(theta[1]),
        covariance=covariance,
        band=(float(p.q[i]), float(p.q[j])),
        rolloff=math.sqrt(kappa) / float(p.q[-1]) if rolloff else None,
        floor=p.floor,
        ends=(long, short),
        bins=j + 1 - i,
        points=(p.q[i : j + 1], p.y[i : j + 1] - kappa * p.u[i : j + 1], p.w[i : j + 1]),
    )


def fit_band(spectrum: Spectrum, band_q: tuple[float, float], slope: float | None = None) -> PowerLaw | None:
    """A straight power law over the bins inside `band_q` (q_low, q_high, rad/m), as the user set it;
    with `slope` given, the intercept alone. None when fewer than 4 bins fall inside."""
    inside = (spectrum.q >= band_q[0]) & (spectrum.q <= band_q[1]) & (spectrum.C > 0)
    if inside.sum() < 4:
        return None
    p = _prepared(spectrum.q[inside], spectrum.C[inside], spectrum.modes[inside], spectrum.scatter[inside])
    theta, covariance, _ = _fit(p, 0, p.x.size - 1, False, slope)
    ends = ("set by the user", "set by the user")
    return PowerLaw(
        float(theta[0]), float(theta[1]), covariance, (float(p.q[0]), float(p.q[-1])), None, 0.0, ends, p.x.size
    )
