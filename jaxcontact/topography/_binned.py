"""A binned spectrum in log-log, as the band's fits use it: each bin's ln C debiased for the log of
a Gamma-distributed mean, its weight, and the coordinates of a Gaussian roll-off (docs/topography.md,
"The band")."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import special

from ._floor import noise_floor
from ._whole import Spectrum

MIN_MODES = 3
# No measured spectrum is a power law to better than about 1 % per bin.
SYSTEMATIC = 0.01
FLOOR_MARGIN_SLOPE = 0.2
FLOOR_MARGIN = 2.0
ORDERS = np.arange(2, 5)
FACTORIALS = np.array([math.factorial(k) for k in ORDERS], dtype=float)


@dataclasses.dataclass(frozen=True)
class Binned:
    x: np.ndarray  # ln q, centred
    x0: float
    y: np.ndarray  # ln C, debiased
    w: np.ndarray  # 1 / variance
    u: np.ndarray  # -(q / q_top)²
    z: np.ndarray  # B × 3: the 2nd to 4th cumulants of u across each bin's modes over k! (`rolloff_offset`)
    q: np.ndarray
    floor: float
    long_cause: str  # what ends the usable bins at the long end
    short_cause: str
    mean: np.ndarray  # the bins' mean periodogram, the floor not subtracted
    shape: np.ndarray  # Gamma shape of each bin's mean: modes / scatter
    # The bins beyond the long end with fewer than `MIN_MODES` modes (as rows of a `Binned`, x centred
    # on this one's x0): too few for a debiased ln C, not for the likelihood of their means.
    long_end: Binned | None = None
    # The bins beyond the short end that the floor's margin left out (raw), where a floor was found.
    short_end: Binned | None = None


def prepare(spectrum: Spectrum, q_max: float | None, q_min: float | None = None) -> Binned | None:
    """The bins a band may use: enough modes, between `q_min` and `q_max`, above a subtracted noise
    floor; None where fewer than five remain."""
    keep = (spectrum.modes >= MIN_MODES) & (spectrum.C > 0)
    long_cause = (
        f"fewer than {MIN_MODES} independent modes per bin beyond it"
        if spectrum.modes[0] < MIN_MODES
        else "the measurement's longest wavelength"
    )
    if q_min is not None and np.any(spectrum.q < q_min):
        keep &= spectrum.q >= q_min
        long_cause = "the waviness cutoff (beyond it the roughness keeps less than 99 % of the amplitude)"
    short_cause = "the grid's shortest wavelength (two spacings)"
    if q_max is not None and np.any(spectrum.q > q_max):
        keep &= spectrum.q <= q_max
        short_cause = "the tip's reliability cutoff"
    q, C, modes, scatter = spectrum.q[keep], spectrum.C[keep], spectrum.modes[keep], spectrum.scatter[keep]
    q2 = (spectrum.q**2 if spectrum.q_squared is None else spectrum.q_squared)[keep]
    cumulants = spectrum.q_squared_cumulants
    cumulants = (np.zeros((spectrum.q.size, ORDERS.size)) if cumulants is None else cumulants)[keep]
    if q.size < 5:
        return None
    floor = noise_floor(q, C, modes, scatter, float(spectrum.slope_of(2.0)) + FLOOR_MARGIN_SLOPE)
    beyond = None
    if floor > 0:
        above = C > FLOOR_MARGIN * floor
        beyond = np.flatnonzero(keep)[~above & (q > q[above][-1] if above.any() else False)]
        q, C, modes, scatter, q2 = q[above], C[above] - floor, modes[above], scatter[above], q2[above]
        cumulants = cumulants[above]
        short_cause = f"the noise floor (within {FLOOR_MARGIN:g}× of it beyond; fitted there beside the power law)"
        if q.size < 5:
            return None
    p = binned(q, C, modes, scatter, floor, long_cause, short_cause, q2, cumulants)
    if beyond is not None and beyond.size:
        p = dataclasses.replace(p, short_end=_rows_of(spectrum, beyond, p))
    few = (spectrum.modes >= 1) & (spectrum.modes < MIN_MODES) & (spectrum.C > 0) & (spectrum.q < q[0])
    few &= spectrum.q >= (q_min or 0.0)
    if not few.any():
        return p
    return dataclasses.replace(p, long_end=_rows_of(spectrum, few, p))


def _rows_of(spectrum: Spectrum, rows, p: Binned) -> Binned:
    """The spectrum's bins `rows` (raw, the floor not subtracted) as a `Binned` in `p`'s coordinates."""
    return binned(
        spectrum.q[rows],
        spectrum.C[rows],
        spectrum.modes[rows],
        spectrum.scatter[rows],
        q_squared=(spectrum.q**2 if spectrum.q_squared is None else spectrum.q_squared)[rows],
        q_squared_cumulants=None if spectrum.q_squared_cumulants is None else spectrum.q_squared_cumulants[rows],
        x0=p.x0,
        q_top=float(p.q[-1]),
    )


def binned(
    q,
    C,
    modes,
    scatter,
    floor=0.0,
    long_cause="",
    short_cause="",
    q_squared=None,
    q_squared_cumulants=None,
    x0=None,
    q_top=None,
) -> Binned:
    """`C` (less `floor`, already) in log-log with its per-bin bias correction and weight; ln q centred
    on `x0` and the roll-off's coordinate on `q_top` (default: their own mean and last bin)."""
    # A bin's mean of `modes` periodogram values of relative variance `scatter` is Gamma-distributed
    # with shape k = modes / scatter: E ln(mean/C) = ψ(k) - ln k, var ln(mean) = ψ'(k).
    k = modes / scatter
    # The floor's subtraction leaves the bin's scatter: relative to what is left, it grows by (C+N)/C.
    variance = special.polygamma(1, k) * ((C + floor) / C) ** 2
    x = np.log(q)
    x0 = float(x.mean()) if x0 is None else x0
    q_top = float(q[-1]) if q_top is None else q_top
    return Binned(
        x=x - x0,
        x0=x0,
        y=np.log(C) - (special.digamma(k) - np.log(k)),
        w=1.0 / (variance + SYSTEMATIC**2),
        u=-(q * q if q_squared is None else q_squared) / q_top**2,
        z=np.zeros((q.size, ORDERS.size))
        if q_squared_cumulants is None
        else q_squared_cumulants * (-1.0 / q_top**2) ** ORDERS / FACTORIALS,
        q=q,
        floor=floor,
        long_cause=long_cause,
        short_cause=short_cause,
        mean=C + floor,
        shape=k,
    )


def rolloff_offset(kappa, z):
    """What a bin's mean of `exp(κ u)` over its modes adds to `κ ū` in ln C: the cumulant series
    `Σ_k κ^k c_k(u) / k!`, k = 2…4 (`z` as `Binned.z`, `kappa` broadcasting against it)."""
    kappa = np.asarray(kappa)[..., None]
    return np.sum(kappa**ORDERS * z, axis=-1)
