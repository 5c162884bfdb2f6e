"""The measured spectrum as the models' input, validated on a measured map (docs/validation.md).

For one areal file: read it (undefined points filled), remove its form (`Curvature()`), characterise
it, and take its binned C2D over the band, cut where the BEM's grid stops resolving it (`l_min` at 4
grid spacings of the map's side), as a `MeasuredSpectrum` rolled off below. A map without a
power-law band has no power-law route (its columns NaN, its status says why); its table is then the
whole binned spectrum, from the map's longest wavelength to the cut. The joint is the map's area.
At loads where the BEM's own contact is at each of `fractions` (on the first realisation: ln F
interpolated in ln A_r between loads where Persson's theory puts it there):

- the BEM on `realisations` periodic realisations of the same spectrum (the surfaces of
  `BEM(spectrum=...)`, solved by `bem.jax_curve`): their mean K, its spread and their contact fraction;
- Persson and GW on the spectrum, Persson's 95 % band from the spectrum's own uncertainty
  (`topography.spectrum_band`), and Persson on the power-law route (the fitted D and G, l_min at the
  same cut) with its 95 % band from (D, G)'s covariance, each as a ratio to the BEM's mean;
- the BEM on the map itself, made periodic by its mirror images: the largest square of it, mirrored,
  Fourier-truncated to `2 grid` points a side (so that it holds wavelengths down to 2 grid spacings
  of the square, shorter than the table's cut) and to square pixels, at the same nominal pressure.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import pathlib

import numpy as np

# The contact fractions of the validation (docs/validation.md).
FRACTIONS = (0.005, 0.015, 0.05, 0.15)
PIXELS_PER_L_MIN = 4


class SpectrumSkipped(Exception):
    """A file the validation cannot use (a line scan, or a band the grid cannot hold); the message says why."""


def mirrored_map_stiffness(roughness, grid: int, modulus: float, loads, area: float):
    """K (N/m, NaN where not ok) and the status of the mirrored map at `loads` on the joint's `area` (module
    docstring). A map of oblong pixels is first cut to its largest square and mirrored, then
    Fourier-truncated along its finer axis to the coarser spacing: square pixels, each of the coarser
    spacing, holding every wavelength both axes resolve."""
    from ..bem import solve
    from ..topography._separate import mirror_tiled
    from ..topography._spectra import grid_spacing

    z = np.asarray(roughness.heights(), dtype=float)
    spacing = np.asarray(grid_spacing(roughness))
    side = float(np.min(roughness.physical_sizes))
    # The largest square, in points along each axis; its mirror image is periodic.
    points = np.minimum(np.rint(side / spacing).astype(int), z.shape)
    square = z[: points[0], : points[1]]
    tiled = mirror_tiled(square - square.mean())
    # Square pixels of the coarser spacing (no more than 2 × grid a side): the Fourier modes both
    # axes hold, each axis's first and last halves kept.
    n = int(min(2 * grid, 2 * points.min()))
    kept = [np.r_[0 : n // 2, 2 * m - n // 2 : 2 * m] for m in points]
    heights = np.real(np.fft.ifft2(np.fft.fft2(tiled)[np.ix_(*kept)])) * n * n / tiled.size
    # The same nominal pressure on the mirrored square (four times the square's area).
    solution = solve(heights, 2 * side, modulus, 4 * np.asarray(loads) * side**2 / area)
    status = np.asarray(solution.status)
    return np.where(status == 0, np.asarray(solution.stiffness) / 4 * area / side**2, np.nan), status


def _status(statuses: dict, i: int, missing: tuple[str, ...] = ()) -> str:
    """ "ok", or each route whose point i is flagged, with its status, and each `missing` one's reason."""
    from ..quantities import status_message

    flagged = [f"{k} {status_message(int(v[i]))}" for k, v in statuses.items() if int(np.asarray(v)[i]) != 0]
    return "; ".join(flagged + list(missing)) or "ok"


@dataclasses.dataclass(frozen=True)
class MeasuredJoint:
    """A measured map as a sample of the joint's roughness (module docstring).

    **Fields:** `scene` (the joint: the map's area and the material; the power-law route's D and G,
    placeholders where `characterisation` is None, with `l_min` at the table's cut), `spectrum` (the
    map's `MeasuredSpectrum`), `characterisation` (None for a map without a power-law band),
    `reference` (`bem.ReferenceCurves`: the BEM on periodic realisations of the spectrum, at loads
    where its first realisation's contact is at the fractions asked for), `mirrored` (K of the
    mirrored map, N/m, NaN where not ok) and `mirrored_status`.
    """

    scene: object
    spectrum: object
    characterisation: object
    reference: object
    mirrored: np.ndarray
    mirrored_status: np.ndarray

    @property
    def loads(self):
        return self.reference.loads


def _bem_loads(curve, topography, guess, fractions):
    """Loads at which the BEM (`curve(topography, loads)`, a `bem.BEMResult`) puts the contact on
    `topography` at `fractions`: ln F interpolated in ln A_r over its contact at the loads `guess`
    (linear, extrapolated beyond them)."""
    from scipy.interpolate import interp1d

    probe = curve(topography, guess)
    ok = (probe.status == 0) & (probe.contact_fraction > 0)
    if ok.sum() < 2:
        return np.asarray(guess)
    log_fraction, log_load = np.log(probe.contact_fraction[ok]), np.log(np.asarray(guess)[ok])
    order = np.argsort(log_fraction)
    along = interp1d(log_fraction[order], log_load[order], fill_value="extrapolate", assume_sorted=True)
    return np.exp(along(np.log(np.asarray(fractions))))


def _jax_curve(topography, loads, modulus):
    from ..bem import jax_curve

    return jax_curve(topography, modulus, loads)


def measured_joint(roughness, material, *, grid: int, realisations: int, fractions, curve=None, band=None, groups=None):
    """The joint view of one map (`MeasuredJoint`).

    **Arguments:** `roughness`, the areal map with its form removed (a SurfaceTopography topography);
    `material`; `grid` and `realisations` of the BEM; the BEM's contact `fractions` at which it is
    loaded; `curve(topography, loads)`, the BEM's `bem.BEMResult` on a periodic map (default
    `bem.jax_curve` with `bem.BEMSettings()`); `band` and `groups`, as `topography.characterise`
    takes them. A map without a power-law band has no characterisation, and its table is its whole
    binned spectrum.

    **Raises:** `SpectrumSkipped` for a band the grid cannot hold.
    """
    from SurfaceTopography import Topography

    from ..bem import BEM, ReferenceCurves
    from ..core import Scene
    from ..numerics import InputError
    from ..physics import MeasuredSpectrum
    from ..quantities import Surface
    from ..topography import NoBandError, characterise
    from ._compare import loads_for_fractions

    try:
        c, whole = characterise(roughness, band=band, groups=groups), None
    except NoBandError as none:  # no power-law route: the measured one alone, on the whole spectrum
        c, whole = None, none.spectrum
    side = math.sqrt(float(np.prod(roughness.physical_sizes)))
    cut = max(0.0 if c is None else c.band[0], PIXELS_PER_L_MIN * side / grid)
    try:
        spectrum = (
            MeasuredSpectrum.from_binned(whole, shortest=cut)
            if c is None
            else MeasuredSpectrum.from_characterisation(c, shortest=cut)
        )
    except InputError as too_few:
        raise SpectrumSkipped(f"{too_few}, the shortest wavelength the grid resolves") from None
    # Without a power-law band the surface's D and G are placeholders: the models that solve on
    # the table do not read them, and the power-law route is not taken.
    surface = Surface(D=1.5, G=1e-12, l_min=cut) if c is None else Surface(D=c.D, G=c.G, l_min=cut)
    scene = Scene(surface, material, side * side)
    modulus = float(material.E)
    if curve is None:
        curve = functools.partial(_jax_curve, modulus=modulus)
    heights = BEM(grid=grid, realisations=realisations, spectrum=spectrum).heights(scene)
    surfaces = [Topography(np.asarray(h, dtype=float), (side, side), periodic=True) for h in heights]
    guess = loads_for_fractions(scene, fractions, spectrum)
    loads = _bem_loads(curve, surfaces[0], guess, fractions)
    results = tuple(curve(s, loads) for s in surfaces)
    reference = ReferenceCurves(results, tuple(range(realisations)), grid, None)
    mirrored = mirrored_map_stiffness(roughness, grid, modulus, loads, side * side)
    return MeasuredJoint(scene, spectrum, c, reference, *mirrored)


def spectrum_validation(path, *, grid: int = 128, realisations: int = 3, fractions=FRACTIONS, modulus=None):
    """Rows (one per fraction) of the validation of one file (module docstring).

    **Arguments:** `path`, an areal topography file; `grid` and `realisations` of the BEM; the BEM's
    contact `fractions`; `modulus`, E* in Pa (default two steel bodies, 210 GPa and ν = 0.3).

    **Raises:** `SpectrumSkipped` for a line scan, or a band the grid cannot hold.
    """
    from ..core import solve
    from ..models import GreenwoodWilliamson, Persson
    from ..quantities import Material
    from ..topography import Curvature, StiffnessBand, read, separate, spectrum_band, stiffness_band

    topography = read(path, fill_undefined=True)
    if topography.dim != 2:
        raise SpectrumSkipped("a line scan: the BEM needs an areal map")
    roughness = separate(topography, Curvature(), None).roughness
    E = 210e9 / (1 - 0.3**2) if modulus is None else modulus
    # Every model compared is elastic: the hardness is not used.
    joint = measured_joint(
        roughness, Material(E=E, nu=0.3, H=3e9), grid=grid, realisations=realisations, fractions=fractions
    )
    scene, spectrum, loads, ref, c = joint.scene, joint.spectrum, joint.loads, joint.reference, joint.characterisation
    # Persson on the measured spectrum, with its band from the spectrum's own uncertainty.
    persson = spectrum_band(scene.with_model(Persson(spectrum=spectrum)), loads)
    gw = solve(scene.with_model(GreenwoodWilliamson(spectrum=spectrum)), loads)
    band = None if c is None else stiffness_band(c, scene.with_model(Persson()), loads)
    mean = ref.mean
    statuses = {"bem": np.max([r.status for r in ref.results], axis=0), "persson": persson.status, "gw": gw.status}
    if band is None:
        nan = np.full_like(mean, np.nan)
        band = StiffnessBand(loads, nan, nan, nan, np.zeros(len(loads), int))
    statuses["power_law"] = band.status
    return [
        {
            "file": pathlib.Path(path).name,
            "D": math.nan if c is None else c.D,
            "l_min_m": float(scene.surface.l_min),
            "load_N": float(loads[i]),
            "contact_fraction_bem": float(ref.contact_fraction[i]),
            "K_bem_N_per_m": float(mean[i]),
            "K_bem_spread": float(ref.stiffness[:, i].std() / mean[i]),
            "map_bem_over_bem": float(joint.mirrored[i] / mean[i]),
            "persson_spectrum_over_bem": float(persson.stiffness[i] / mean[i]),
            "spectrum_band_low_over_bem": float(persson.lower[i] / mean[i]),
            "spectrum_band_high_over_bem": float(persson.upper[i] / mean[i]),
            "gw_spectrum_over_bem": float(gw.stiffness[i] / mean[i]),
            "persson_power_law_over_bem": float(band.stiffness[i] / mean[i]),
            "power_law_band_low_over_bem": float(band.lower[i] / mean[i]),
            "power_law_band_high_over_bem": float(band.upper[i] / mean[i]),
            "status": _status(statuses, i, () if c is not None else ("power_law: the map has no power-law band",)),
        }
        for i in range(len(loads))
    ]
