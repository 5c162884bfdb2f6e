"""One surface measured several times (a stylus profile and an optical map at two magnifications): each
measurement's spectrum in its own power-law band, joined, and one W-M power law fitted over the union
(docs/topography.md, "Several measurements of one surface")."""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from ..numerics._validate import InputError, spelled
from . import _spectra as spectra
from ._band import CALIBRATION, PowerLaw, select_band
from ._kind import Stitched
from ._psd import NoBandError, _q_and_D
from ._result import Characterisation
from ._separate import lowest_roughness_q
from ._whole import local_slopes, whole_spectrum

# Above this χ²/ν of the joint power law the measurements are not of one spectrum: a unit or
# calibration mistake, or two surfaces.
MISMATCH = 3.0


def _measured(topography, index: int):
    rows, _, _, periodic, kind = spectra.rows_of(topography)
    spectrum = whole_spectrum(kind.heights(rows), spectra.grid_spacing(topography), periodic)
    cutoff = topography.short_reliability_cutoff()
    law = select_band(spectrum, None if not cutoff else 2 * math.pi / cutoff, q_min=lowest_roughness_q(topography))
    if not isinstance(law, PowerLaw):
        raise NoBandError(
            f"measurement {index + 1} has no power-law band of its own to join (characterise it alone to see why)",
            spectrum,
            _q_and_D(local_slopes(spectrum)),
            law,
        )
    return kind, spectrum, law


def _check_distinct(topographies) -> None:
    """Refuse a measurement given twice: its bins would count twice and shrink the intervals."""
    for j, b in enumerate(topographies):
        for i, a in enumerate(topographies[:j]):
            if a.nb_grid_pts == b.nb_grid_pts and np.array_equal(a.heights(), b.heights()):
                raise InputError(
                    f"topographies {i + 1} and {j + 1} are the same measurement (equal heights): each counted twice "
                    "would make the intervals look twice as well determined; give each measurement once"
                )


def characterise_stitched(topographies, *, accept_mismatch: bool = False) -> Characterisation:
    """D, G and l_min from several measurements of one surface: each in its own band (as `characterise`
    finds it, floor and roll-off taken out), one power law in (D, ln G) over all their bins, profiles'
    `C1D` and maps' `C2D` each with its own prefactor. The covariance is the weighted least-squares
    one (scaled by χ²/ν where above 1) plus, per measurement, a 1 % uncertainty of its height scale and
    the change when its band's short end moves in by a factor 2.

    **Arguments:** `topographies`, two or more SurfaceTopography line scans or maps in metres, each a
    different measurement; `accept_mismatch`, return the joint fit even where the measurements do not
    join into one power law (χ²/ν > 3; then a diagnostic says so) instead of refusing them.
    **Returns:** a `Characterisation` (method "psd", kind `Stitched()` where kinds differ).

    **Raises:** `ValueError` for fewer than two measurements, a measurement given twice, and (unless
    `accept_mismatch`) measurements that do not join: their height scales, lateral calibrations or
    the surfaces measured differ, and a joint D would lie outside what each says.
    """
    if len(topographies) < 2:
        raise InputError(f"topographies: {len(topographies)} given; stitching needs at least 2 measurements")
    _check_distinct(topographies)
    measured = [_measured(t, k) for k, t in enumerate(topographies)]
    kinds = [m[0] for m in measured]
    points = [(kind, *law.points) for kind, _, law in measured]

    def residuals(theta, shifts=None, trimmed=-1):
        D, log_G = theta
        out = []
        for m, (kind, q, y, w) in enumerate(points):
            model = kind.log_prefactor(D, log_G) + kind.spectral_slope(D) * np.log(q)
            # The band's own systematic, as for one measurement: its short end moved in by a factor 2.
            kept = q <= q[-1] / 2 if m == trimmed else np.ones(q.size, bool)
            out.append(np.sqrt(w) * (y + (0.0 if shifts is None else shifts[m]) - model) * kept)
        return np.concatenate(out)

    first_kind, first_spectrum, first = measured[0]
    D0 = float(np.clip(first_spectrum.D_of(first.slope), 1.05, 1.95))
    start = [D0, first_kind.log_G_of_prefactor(D0, first.intercept)]
    bounds = ([1.0 + 1e-6, -np.inf], [2.0 - 1e-6, np.inf])
    fit = optimize.least_squares(residuals, start, bounds=bounds, x_scale=[0.1, 1.0])
    D_hat, log_G_hat = fit.x
    if not (bounds[0][0] + 1e-3 < D_hat < bounds[1][0] - 1e-3 and -700.0 < log_G_hat < 700.0):
        alone = ", ".join(f"{s.D_of(law.slope):.3g}" for _, s, law in measured)
        raise InputError(
            f"the measurements do not join into one power law with 1 < D < 2: the joint fit runs to D = {D_hat:.4g} "
            f"(alone they give D = {alone}); their height scales, lateral calibrations or the surfaces measured "
            "differ: characterise them one by one"
        )
    n = fit.fun.size
    chi2 = 2 * fit.cost
    covariance = np.linalg.inv(fit.jac.T @ fit.jac) * max(1.0, chi2 / (n - 2))
    for m in range(len(points)):
        for args in ((np.eye(len(points))[m] * CALIBRATION,), (None, m)):
            moved = optimize.least_squares(residuals, fit.x, bounds=bounds, x_scale=[0.1, 1.0], args=args).x - fit.x
            covariance = covariance + np.outer(moved, moved)
    diagnostics = ()
    if chi2 / (n - 2) > MISMATCH:
        alone = ", ".join(f"{s.D_of(law.slope):.3g}" for _, s, law in measured)
        mismatch = (
            f"the measurements do not join into one power law (χ²/ν = {chi2 / (n - 2):.3g}; jointly D = {D_hat:.3g}, "
            f"alone D = {alone}): their height scales, their lateral calibrations or the surfaces measured differ"
        )
        if not accept_mismatch:
            insist = spelled("accept_mismatch=True", "--accept-mismatch")
            raise InputError(f"{mismatch}: characterise them one by one (or give {insist} to fit them jointly anyway)")
        diagnostics += (f"{mismatch}; the intervals include the misfit",)
    dof = max(n - 2, 2)
    # The bins the joint fit uses (a band's long-end few-mode bins are in its own likelihood fit only).
    shortest = min(2 * math.pi / q[-1] for _, q, _, _ in points)
    longest = max(2 * math.pi / q[0] for _, q, _, _ in points)
    q_all = np.concatenate([q for _, q, _, _ in points])
    C_all = np.exp(np.concatenate([y for _, _, y, _ in points]))
    fit_q = np.geomspace(q_all.min(), q_all.max(), 50)
    fit_C = np.exp(first_kind.log_prefactor(D_hat, log_G_hat) + first_kind.spectral_slope(D_hat) * np.log(fit_q))
    return Characterisation.fitted(
        "psd",
        float(D_hat),
        float(log_G_hat),
        (shortest, longest),
        covariance,
        dof,
        groups=len(points),
        estimates=np.array([[float(s.D_of(law.slope)), math.nan] for _, s, law in measured]),
        spectrum=(q_all, C_all),
        fit=(fit_q, fit_C),
        diagnostics=diagnostics,
        kind=kinds[0] if len(set(kinds)) == 1 else Stitched(),
        reliability_cutoff=None,
        ends=(
            "the longest band's long end among the measurements",
            "the shortest band's short end among the measurements",
        ),
    )
