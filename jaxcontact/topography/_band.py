"""Where a measured spectrum is a power law: the band a fit may use, found from the data.

The criterion (docs/topography.md, "The band"): among all windows of the binned spectrum
(`_whole.Spectrum`) spanning at least a factor `MIN_RATIO` in q, with at least `MIN_MODES`
independent modes in every bin, take the *widest* in log q in which

1. a straight line in log-log fits within the bins' own scatter (χ² ≤ ν + 3√(2ν), the variance of
   ln C per bin being the periodogram's scatter over its modes plus `SYSTEMATIC`²), and
2. a parabola does not improve on it (its quadratic coefficient within 3 standard errors of 0), and
3. the bin at its short end lies within 3 of its standard deviations of the line (χ² is blind to one
   bin that a sharp cutoff halves, where an artefact begins), and
4. the slope gives 1 < D < 2.

Instruments add three artefacts that the window's ends must exclude. A white **noise floor** (a
spectrum that flattens at its short end, its slope `FLOOR_MARGIN_SLOPE` above that of D = 2, shallower than any
self-affine one) is estimated from the top octave and subtracted; bins within `FLOOR_MARGIN`× of it are
left out. A **transfer function** (an optical profiler's lateral resolution, a tip) rolls the spectrum
off gradually, which a straight line absorbs by tilting: a window may therefore carry a Gaussian
roll-off `exp(-κ q²)` as a third term where that term is significant (3 standard errors) and
corrects by at most `ROLLOFF_CAP` in ln C (a bin's mean of `exp(-κ q²)` over its modes is
`exp(-κ⟨q²⟩)` times the cumulant series `exp(Σ_k (-κ)^k c_k(q²)/k!)`, k = 2…4: without it a strong
roll-off is under-corrected across a bin, and D biased low); the better determined of the widest straight and corrected
windows is chosen, unless the straight one is tilted by the roll-off (`_tilted`). A **sharp cutoff**
(a low-pass filter) fails test 1 or 3 at once. The tip's reliability cutoff, where known, bounds the band
from the start.

The windows are found by weighted least squares on the debiased ln C. The chosen window's power law
is then fitted by the likelihood of its bins' means (`_likelihood`), which needs no debiasing and so
takes the long end's few-mode bins too, and beside a floor fits the floor over the bins beyond its
margin. Its covariance (the inverse Fisher information, scaled by Pearson's χ² per degree of freedom
where above 1) has the band's own systematic added: the change of (slope, intercept) when either end
moves in by a factor 2.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ._binned import MIN_MODES, ORDERS, SYSTEMATIC, Binned, binned, prepare, rolloff_offset
from ._likelihood import likelihood_fit
from ._whole import Spectrum

MIN_RATIO = 4.0
Z = 3.0
# An instrument's height scale is not known to better than about 1 %: 2 % in C, the same at every q.
CALIBRATION = 0.02
ROLLOFF_CAP = 12.0
ROLLOFF_PASSES = 2
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


def _all_windows(p: Binned, columns):
    """Weighted least squares on `columns` over every window [i, j] (j ≥ i + 4), by cumulative moments.

    **Returns:** `solve(kappa=None)`, giving coefficients, their unscaled covariance, χ² and degrees
    of freedom as B × B arrays, of `p.y`, or with `kappa` (B × B, per window) of `p.y` less
    `rolloff_offset(kappa, p.z)` (a roll-off's mean over each bin's modes: linear in the series `p.z`,
    whose moments are taken once); and which windows are valid.
    """
    X = np.stack(columns, axis=-1)
    Y = np.column_stack([p.y, -p.z])
    k = X.shape[1]
    cumulative = lambda a: np.concatenate([np.zeros((1,) + a.shape[1:]), np.cumsum(a, axis=0)])  # noqa: E731
    B = p.x.size
    long_end, short_end = np.meshgrid(np.arange(B), np.arange(B), indexing="ij")
    valid = short_end - long_end >= 4
    Ic, Jc = np.where(valid, long_end, 0), np.where(valid, short_end, 4)
    window = lambda a: (lambda c: c[Jc + 1] - c[Ic])(cumulative(a))  # noqa: E731
    outer = lambda a, b: p.w[:, None, None] * a[:, :, None] * b[:, None, :]  # noqa: E731
    inverse = np.linalg.inv(window(outer(X, X)) + (~valid)[..., None, None] * np.eye(k))
    XY, YY = window(outer(X, Y)), window(outer(Y, Y))
    dof = np.maximum(Jc - Ic + 1 - k, 1)

    def solve(kappa=None):
        b = np.zeros(valid.shape + (Y.shape[1],))
        b[..., 0] = 1.0
        if kappa is not None:
            b[..., 1:] = kappa[..., None] ** ORDERS
        r = np.einsum("...il,...l->...i", XY, b)
        coefficients = np.einsum("...ij,...j->...i", inverse, r)
        chi2 = np.einsum("...l,...lm,...m->...", b, YY, b) - np.einsum("...i,...i->...", coefficients, r)
        return coefficients, inverse, np.maximum(chi2, 0.0), dof

    return solve, valid


def _short_end(p: Binned, columns, coefficients, kappa=None):
    """Each window's residual at its short-end bin, in that bin's standard deviations (B × B)."""
    y = p.y[None, :] - (0.0 if kappa is None else rolloff_offset(kappa, p.z[None, :, :]))
    return (y - np.einsum("ijk,jk->ij", coefficients, np.stack(columns, axis=-1))) * np.sqrt(p.w)[None, :]


def _widest(p: Binned, ok):
    if not ok.any():
        return None
    span = np.where(ok, p.x[None, :] - p.x[:, None], -1.0)
    return np.unravel_index(int(np.argmax(span)), span.shape)


def _windows(p: Binned, D_of):
    one = np.ones_like(p.x)
    solve, valid = _all_windows(p, [one, p.x])
    line, line_inv, line_chi2, line_dof = solve()
    quad, quad_inv, quad_chi2, quad_dof = _all_windows(p, [one, p.x, p.x * p.x])[0]()
    solve = _all_windows(p, [one, p.x, p.u])[0]
    roll, roll_inv, roll_chi2, roll_dof = solve()
    kappa = None
    # Each window's κ from the pass before gives its bins' offsets.
    for _ in range(ROLLOFF_PASSES):
        kappa = roll[..., 2]
        roll, roll_inv, roll_chi2, roll_dof = solve(kappa)
    line_end = _short_end(p, [one, p.x], line)
    roll_end = _short_end(p, [one, p.x, p.u], roll, kappa)
    J = np.arange(p.x.size)[None, :]
    wide = valid & (p.x[None, :] - p.x[:, None] >= math.log(MIN_RATIO))
    passes = lambda chi2, dof: chi2 <= dof + Z * np.sqrt(2 * dof)  # noqa: E731
    straight = (
        wide
        & passes(line_chi2, line_dof)
        & (np.abs(line_end) <= Z)
        & (np.abs(quad[..., 2]) <= Z * np.sqrt(quad_inv[..., 2, 2] * np.maximum(1, quad_chi2 / quad_dof)))
        & (D_of(line[..., 1]) > 1)
        & (D_of(line[..., 1]) < 2)
    )
    kappa_z = roll[..., 2] / np.sqrt(roll_inv[..., 2, 2] * np.maximum(1, roll_chi2 / roll_dof))
    rolled = (
        wide
        & passes(roll_chi2, roll_dof)
        & (np.abs(roll_end) <= Z)
        & (kappa_z > Z)
        & (roll[..., 2] * -p.u[J] <= ROLLOFF_CAP)
        & (D_of(roll[..., 1]) > 1)
        & (D_of(roll[..., 1]) < 2)
    )
    return straight, rolled, line_chi2 / line_dof, D_of(line[..., 1]), wide


def _fit(p: Binned, i: int, j: int, rolloff: bool, slope: float | None = None):
    """(slope, intercept at q = 1), their covariance, and κ, over bins i..j; with `slope` given, the
    intercept (and κ) alone."""
    s = slice(i, j + 1)
    measured = p.y[s] if slope is None else p.y[s] - slope * (p.x[s] + p.x0)
    columns = [np.ones(j + 1 - i)] + ([p.x[s]] if slope is None else []) + ([p.u[s]] if rolloff else [])
    X = np.stack(columns, axis=-1)
    w = p.w[s]
    inverse = np.linalg.inv(X.T @ (w[:, None] * X))
    y = measured
    c = inverse @ (X.T @ (w * y))
    for _ in range(ROLLOFF_PASSES if rolloff else 0):
        y = measured - rolloff_offset(c[-1], p.z[s])
        c = inverse @ (X.T @ (w * y))
    dof = max(X.shape[0] - X.shape[1], 1)
    chi2 = float(np.sum(w * (y - X @ c) ** 2))
    # The least-squares fit is the start of the likelihood's, which replaces it where it converges.
    refined = likelihood_fit(p, i, j, rolloff, c, slope)
    long_end = False
    if refined is not None:
        c, inverse, chi2, dof, long_end = refined
    to_physical = np.zeros((2, X.shape[1]))
    if slope is None:
        to_physical[0, 1] = 1.0
        to_physical[1, 0], to_physical[1, 1] = 1.0, -p.x0  # intercept at ln q = 0
        theta = to_physical @ c
    else:
        to_physical[1, 0] = 1.0
        theta = np.array([slope, c[0]])
    covariance = to_physical @ inverse @ to_physical.T * max(1.0, chi2 / dof) + np.diag([0.0, CALIBRATION**2])
    return theta, covariance, (float(c[-1]) if rolloff else 0.0), long_end


def _with_systematics(p: Binned, i: int, j: int, rolloff: bool, slope):
    """`_fit` over bins i..j, its covariance with the band's systematic: the change when either end
    moves in by a factor 2."""
    theta, covariance, kappa, long_end = _fit(p, i, j, rolloff, slope)
    shorter = int(np.searchsorted(p.x, p.x[j] - TRIM, side="right")) - 1
    longer = int(np.searchsorted(p.x, p.x[i] + TRIM, side="left"))
    for start, stop in ((i, shorter), (longer, j)):
        if stop - start >= 4:
            moved = _fit(p, start, stop, rolloff, slope)[0] - theta
            covariance = covariance + np.outer(moved, moved)
    return theta, covariance, kappa, long_end


def _tilted(p: Binned, straight, corrected) -> bool:
    """Whether the straight fit (`((theta, covariance, kappa, long_end), (i, j), rolloff)`, as `corrected`) is a
    line tilted by the corrected fit's roll-off, which its own tests cannot see where the roll-off and
    the slope are nearly collinear: inside the corrected window, lowered at its short end by more
    than `Z · SYSTEMATIC` in ln C, its slope off by more than the two's combined standard error."""
    ((theta, covariance, *_), (i, j), _), ((theta_c, covariance_c, kappa, _), (ci, cj), _) = straight, corrected
    within = ci <= i and cj >= j and kappa * -p.u[j] > Z * SYSTEMATIC
    return bool(within and abs(theta[0] - theta_c[0]) > math.sqrt(covariance[0, 0] + covariance_c[0, 0]))


def select_band(
    spectrum: Spectrum, q_max: float | None = None, slope: float | None = None, q_min: float | None = None
) -> PowerLaw | tuple[float, float] | None:
    """The widest power-law band of `spectrum` (the module's criterion), within `[q_min, q_max]`;
    with `slope` given, the power law's intercept alone over that band (D held).

    **Returns:** a `PowerLaw`; or, where no window passes, the wavelengths (short, long) in m of the
    window that comes closest (the best straight fit with 1 < D < 2 over a factor 4), to suggest;
    or None when no stretch of the spectrum has a self-affine slope.
    """
    p = prepare(spectrum, q_max, q_min)
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
    (theta, covariance, kappa, long_end), (i, j), rolloff = chosen
    short = (
        p.short_cause
        if j == p.x.size - 1
        else "beyond it the spectrum rolls off faster than the corrected Gaussian transfer function"
        if rolloff
        else "beyond it the spectrum departs from the power law (a roll-off, filter or noise)"
    )
    long = "beyond it the spectrum departs from the power law"
    inside = slice(i, j + 1)
    longest = float(p.q[i])
    if i == 0:
        long = p.long_cause
        if long_end:
            longest = float(p.long_end.q[0])
            long = f"the measurement's longest wavelength (bins of < {MIN_MODES} modes in the likelihood fit only)"
    return PowerLaw(
        slope=float(theta[0]),
        intercept=float(theta[1]),
        covariance=covariance,
        band=(longest, float(p.q[j])),
        rolloff=math.sqrt(kappa) / float(p.q[-1]) if rolloff else None,
        floor=p.floor,
        ends=(long, short),
        bins=j + 1 - i,
        points=(p.q[inside], p.y[inside] - kappa * p.u[inside] - rolloff_offset(kappa, p.z[inside]), p.w[inside]),
    )


def fit_band(spectrum: Spectrum, band_q: tuple[float, float], slope: float | None = None) -> PowerLaw | None:
    """A straight power law over the bins inside `band_q` (q_low, q_high, rad/m), as the user set it;
    with `slope` given, the intercept alone. None when fewer than 4 bins fall inside."""
    inside = (spectrum.q >= band_q[0]) & (spectrum.q <= band_q[1]) & (spectrum.C > 0)
    if inside.sum() < 4:
        return None
    p = binned(spectrum.q[inside], spectrum.C[inside], spectrum.modes[inside], spectrum.scatter[inside])
    theta, covariance, *_ = _fit(p, 0, p.x.size - 1, False, slope)
    ends = ("set by the user", "set by the user")
    return PowerLaw(
        float(theta[0]), float(theta[1]), covariance, (float(p.q[0]), float(p.q[-1])), None, 0.0, ends, p.x.size
    )
