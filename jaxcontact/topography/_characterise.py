"""D, G and l_min of a measured or synthetic topography, with uncertainty (docs/model.md §8)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..numerics._validate import InputError, assigned, check_choice, spelled
from . import _spectra as spectra
from ._checks import implausible, widened_for_filling
from ._conventions import structure_function_constant
from ._kind import AbstractMeasurementKind
from ._psd import characterise_spectrum
from ._result import Characterisation

METHODS = ("psd", "structure-function")
# The structure function's band: from this many grid spacings (near the grid, a roll-off or filter
# bends it first) to a fraction of a group's scan. The structure function of a finite, detrended
# scan falls below the power law at lags that are a sizeable fraction of it (10-30 % at a sixteenth
# for D = 1.3), so its band stops far short of the scan; where that leaves less than the factor 4 a
# fit needs, it reaches to a quarter of it.
SHORTEST_IN_PIXELS = 10
LONGEST_FRACTION = 0.02
WIDEST_FRACTION = 0.25


def characterise(topography, *, band=None, method: str = "psd", groups: int | None = None, D=None):
    """Fit the W-M power law to a topography's spectrum (or structure function).

    **Arguments:**

    - `topography`: a SurfaceTopography line scan or map in metres (from `read` or `synthesis`).
    - `band`: (shortest, longest) wavelength to fit, m. Default (PSD): the widest band where the
      spectrum is a power law, found from the data (docs/topography.md, "The band"), within the
      tip's reliability cutoff; (structure function) from `max(10 grid spacings, the cutoff)` to a
      fiftieth of a group's scan length.
    - `method`: "psd" (the whole measurement's spectrum: the radially averaged `C2D = C0 q^-(6-2D)` of
      a map, `C1D = K1 q^-(5-2D)` of a profile; uncertainty from the periodogram's own scatter per
      bin and the band's position) or "structure-function" (`S ∝ τ^(4-2D)` of line scans,
      uncertainty from the scatter between groups).
    - `groups`: (structure function) independent groups whose scatter gives the uncertainty: blocks
      of line scans of a map (default 16) or segments of a profile (default 8).
    - `D`: hold D at this value and fit the amplitude alone.

    **Returns:** a `Characterisation`. **Raises:** `ValueError` naming the bad argument, or
    saying why no power law can be fitted (band outside the data, profile too short); where no
    band is found, a `NoBandError` that carries the spectrum and a suggested band.
    """
    check_choice("method", method, METHODS)
    rows, dx, length, periodic, kind = spectra.rows_of(topography)
    if not np.ptp(rows) > 0:
        raise InputError(f"the {kind.noun} is flat: every height is the same, so it has no roughness to characterise")
    if groups is not None and (isinstance(groups, bool) or not isinstance(groups, int) or groups < 3):
        raise InputError(f"{assigned('groups', repr(groups))} must be an integer >= 3 (independent groups)")
    if method == "psd":
        # A map's rings are whole to the coarser axis's Nyquist wavevector: two of its spacings.
        spacing = spectra.grid_spacing(topography)
        coarser = float(np.max(spacing))
        band = None if band is None else _checked_band(band, coarser, length, kind, rows.shape[1])
        heights = kind.heights(rows)
        cutoff = topography.short_reliability_cutoff()
        c = characterise_spectrum(topography, heights, spacing, periodic, kind, band, D, cutoff)
        return dataclasses.replace(c, diagnostics=c.diagnostics + implausible(float(np.std(rows)), c))
    blocks = kind.groups(rows, groups)
    periodic = periodic and len(blocks) == 1
    if len(blocks) < 3:
        raise InputError(f"{assigned('groups', str(len(blocks)))}: at least 3 independent groups are needed")
    segment = blocks[0].shape[1] * dx
    cutoff = topography.short_reliability_cutoff()
    shortest = max(SHORTEST_IN_PIXELS * dx, cutoff or 0.0)
    if band is None:
        longest = min(max(LONGEST_FRACTION * segment, 4 * shortest), WIDEST_FRACTION * segment)
        if longest < 4 * shortest:
            raise InputError(
                f"the {kind.noun} is too small for any power-law band: "
                f"{rows.shape[1]} points over {length:.3g} m leave wavelengths {shortest:.3g}-{longest:.3g} m "
                "to fit (a factor 4 at least is needed; "
                f"{spelled('fewer groups', 'a smaller --groups')} give longer segments)"
            )
        band = (shortest, longest)
    band = _checked_band(band, dx, segment, kind, rows.shape[1])
    x, per_group, weights = spectra.binned_structure_function(blocks, dx, band)
    exponent = lambda slope: (4 - slope) / 2  # noqa: E731  slope = 4 - 2D
    log_G = lambda D_, intercept: (intercept - math.log(structure_function_constant(D_))) / (2 * (D_ - 1))  # noqa: E731
    slope_of = lambda D_: 4 - 2 * D_  # noqa: E731
    if x.size < 4:
        raise InputError(f"{_band(band)} holds {x.size} spectral bins: too few to fit")
    log_x, log_y = np.log(x), np.log(per_group)
    mean_y = np.log(per_group.mean(axis=0))

    def estimate(curve):
        if D is not None:
            return float(D), float(np.average(curve - slope_of(float(D)) * log_x, weights=weights))
        # Weighted by the periodogram values in each bin: a bin's mean is as good as its count.
        slope, intercept = spectra.line_fit(log_x, curve, weights)
        return float(exponent(slope)), float(intercept)

    def to_D_logG(curve):
        D_hat, intercept = estimate(curve)
        return D_hat, (log_G(D_hat, intercept) if 1 < D_hat < 2 else math.nan), intercept

    D_fit, log_G_fit, intercept = to_D_logG(mean_y)
    if not 1 < D_fit < 2:
        raise InputError(
            f"no power-law band: the slope over ({band[0]:.3g}, {band[1]:.3g}) m gives D = {D_fit:.3g}, "
            "outside (1, 2); the surface is not self-affine there (another band may be: "
            f"{spelled('band=(short, long)', '--band SHORT LONG')})"
        )
    estimates = np.array([to_D_logG(curve)[:2] for curve in log_y])
    n = len(estimates)
    # The estimate fits the groups' mean spectrum (the log of one group's few periodogram values
    # per bin is biased low); the scatter between the groups' own fits is its uncertainty.
    usable = np.all(np.isfinite(estimates), axis=1)
    D_hat, log_G_hat = D_fit, log_G_fit
    if usable.sum() < 3:
        raise InputError(
            f"no power-law band: only {usable.sum()} of {n} groups give D in (1, 2) over "
            f"({band[0]:.3g}, {band[1]:.3g}) m; the surface is not self-affine there"
        )
    n = int(usable.sum())
    covariance = np.cov(estimates[usable].T) / n
    diagnostics = _diagnostics(log_x, log_y, mean_y, slope_of(D_hat), estimates)
    filled = float(topography.info.get("filled_fraction", 0.0))
    if filled > 0:
        covariance, note = widened_for_filling(covariance, filled, held=D is not None)
        diagnostics += (note,)
    fit_x = np.geomspace(x[0], x[-1], 50)
    return Characterisation.fitted(
        method,
        D_hat,
        log_G_hat,
        band,
        covariance,
        n - 1,
        held=D is not None,
        groups=n,
        estimates=estimates,
        spectrum=spectra.full_structure_function(blocks, dx),
        fit=(fit_x, np.exp(intercept + slope_of(D_hat) * np.log(fit_x))),
        diagnostics=diagnostics,
        kind=kind,
        reliability_cutoff=cutoff,
    )


def _checked_band(band, dx: float, longest: float, kind: AbstractMeasurementKind, points: int) -> tuple[float, float]:
    """`band` as two floats, after checking it is inside the data (`2 dx` to `longest`) and spans a factor 4."""
    band = tuple(float(b) for b in band)
    if len(band) != 2 or not (0 < band[0] < band[1]):
        raise InputError(f"{_band(band)} must be (shortest, longest) wavelengths with 0 < shortest < longest")
    if band[0] < 2 * dx or band[1] > longest:
        raise InputError(
            f"{_band(band)} is outside the data: wavelengths must lie in "
            f"[{2 * dx:.3g}, {longest:.3g}] m (two grid spacings to one {kind.piece})"
        )
    if band[1] / band[0] < 4:
        raise InputError(
            f"{_band(band)} spans less than a factor 4 in wavelength: the "
            f"{kind.noun} is too short for any power-law band ({points} points)"
        )
    return band


def _band(band) -> str:
    short, long = band[:2] if len(band) >= 2 else (band + (math.nan, math.nan))[:2]
    return assigned("band", spelled(f"({short:.3g}, {long:.3g})", f"{short:.3g} {long:.3g}")) + " m"


def _diagnostics(log_x, log_y, mean_y, slope, estimates) -> tuple[str, ...]:
    notes = []
    # Curvature of log C against log x beyond its scatter between groups: not a power law in the band.
    curvatures = spectra.curvature(log_x, log_y)
    mean_curvature = spectra.curvature(log_x, mean_y)
    spread = np.std(curvatures, ddof=1) / math.sqrt(len(curvatures))
    span = log_x[-1] - log_x[0]
    slope_change = abs(2 * mean_curvature * span)
    if abs(mean_curvature) > 3 * spread and slope_change > 0.3:
        notes.append(
            f"the spectrum is not a power law in the band: its log-log slope changes by {slope_change:.2f} "
            f"across it (at {3 * spread * 2 * span:.2f} scatter); D and G describe an average, try a narrower band"
        )
    if not np.all(np.isfinite(estimates)):
        notes.append("some groups give D outside (1, 2): their spectra are not self-affine in the band")
    return tuple(notes)
