"""Form, waviness and roughness apart (docs/topography.md, "Form and waviness").

A measured map is the part's form (tilt, curvature of the part, a lens's figure), its waviness
(tool marks, chatter, the mesoscale gap of a joint) and its roughness. The contact models describe
the roughness alone; the waviness is a mesoscale gap in series with it. `separate` removes the form
as a least-squares polynomial (SurfaceTopography's detrending for a tilt or a curvature; numpy's
Legendre basis for a higher degree) and splits what is left at a cutoff wavelength `λc` by the
Gaussian filter of ISO 16610-21/-61 (scipy's `gaussian_filter`): the waviness keeps a wavelength
λ with amplitude `exp(-π (α λc/λ)²)`, `α = sqrt(ln 2 / π)` (half of it at λc), and the roughness
keeps the rest, so that form + waviness + roughness is the map exactly.
"""

from __future__ import annotations

import abc
import dataclasses
import math
import numbers
from typing import ClassVar

import equinox as eqx
import numpy as np

from ..numerics._validate import InputError, check_strategy, optional_import
from ._read import from_heights

# ISO 16610-21: the Gaussian weighting function's constant; the filter passes half the amplitude at λc.
ALPHA = math.sqrt(math.log(2.0) / math.pi)
# The roughness keeps at least this share of a wavelength's amplitude inside the band a fit may use.
KEPT = 0.99


class AbstractForm(eqx.Module):
    """A form to remove from a measurement: a least-squares surface of a few parameters.

    **Class attribute:** `name`, as reports write it.
    """

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def heights(self, topography) -> np.ndarray:
        """The form's heights (m) on the topography's grid."""


def _detrended_form(topography, mode: str) -> np.ndarray:
    return np.asarray(topography.heights()) - np.asarray(topography.detrend(mode).heights())


class Mean(AbstractForm):
    """The mean height alone (what `read` already removes): no form."""

    name: ClassVar[str] = "mean"

    def heights(self, topography):
        return _detrended_form(topography, "center")


class Tilt(AbstractForm):
    """The plane of least rms height (SurfaceTopography's `detrend("height")`)."""

    name: ClassVar[str] = "tilt"

    def heights(self, topography):
        return _detrended_form(topography, "height")


class Curvature(AbstractForm):
    """The second-order polynomial of least rms height (SurfaceTopography's `detrend("curvature")`):
    a tilt and a curvature, as of a cylinder, a sphere or a saddle."""

    name: ClassVar[str] = "curvature"

    def heights(self, topography):
        return _detrended_form(topography, "curvature")


class Polynomial(AbstractForm):
    """The polynomial of total degree `degree` (1–10) of least rms height (`polynomial_fit`)."""

    name: ClassVar[str] = "polynomial"
    degree: int = eqx.field(static=True, default=3)

    def __check_init__(self):
        if isinstance(self.degree, bool) or not isinstance(self.degree, int) or not 1 <= self.degree <= 10:
            raise InputError(f"degree = {self.degree!r} must be an integer in [1, 10]")

    def heights(self, topography):
        return polynomial_fit(np.asarray(topography.heights(), dtype=float), self.degree)


def polynomial_fit(z: np.ndarray, degree: int) -> np.ndarray:
    """The least-squares polynomial of total degree `degree` through a profile or map `z`, on its grid.

    Legendre polynomials of the coordinates scaled to [-1, 1] are near orthogonal on the grid, so the
    normal equations (a few columns against millions of rows) are well conditioned.
    """
    sides = [np.polynomial.legendre.legvander(np.linspace(-1.0, 1.0, n), degree) for n in z.shape]
    if z.ndim == 1:
        basis = sides[0]
    else:
        columns = [
            np.outer(sides[0][:, i], sides[1][:, j]).ravel() for i in range(degree + 1) for j in range(degree + 1 - i)
        ]
        basis = np.stack(columns, axis=-1)
    coefficients = np.linalg.solve(basis.T @ basis, basis.T @ z.ravel())
    return (basis @ coefficients).reshape(z.shape)


# The forms by name, as the command line gives them (`--form`).
FORMS = {form.name: form for form in (Curvature, Tilt, Polynomial, Mean)}


@dataclasses.dataclass(frozen=True)
class Separated:
    """A measurement in three parts, each a height array (m) on its grid: `form + waviness + roughness`
    is the measurement.

    **Fields:** `roughness` (a SurfaceTopography object, for `characterise` and the models: its
    `info["waviness_cutoff"]` bounds the band a spectrum fit may use), `waviness` (heights, zeros
    without a cutoff: the mesoscale gap), `form_heights`, `form` (the `AbstractForm` removed),
    `waviness_cutoff` (λc, m, or None).
    """

    roughness: object
    waviness: np.ndarray
    form_heights: np.ndarray
    form: AbstractForm
    waviness_cutoff: float | None

    def removed(self) -> str:
        """What was taken out, in words, with the rms height of each part (the roughness's
        `info["separation"]`)."""
        return self.roughness.info["separation"]


def _rms(z) -> float:
    return float(np.sqrt(np.mean(np.square(z))))


def _removed(form, form_heights, waviness, cutoff, roughness) -> str:
    name = form.name + (f" of degree {form.degree}" if isinstance(form, Polynomial) else "")
    text = f"form removed: {name} (rms {_rms(form_heights):.3g} m)"
    if cutoff is not None:
        text += (
            f"; waviness above {cutoff:.3g} m split off by the ISO 16610 Gaussian filter (rms {_rms(waviness):.3g} m)"
        )
    return text + f"; roughness rms {_rms(roughness):.3g} m"


def longest_roughness_wavelength(cutoff: float) -> float:
    """The longest wavelength whose amplitude the roughness keeps to `KEPT` after the Gaussian split at
    `cutoff` (m): `1 - exp(-π (α λc/λ)²) = KEPT`, about λc/2.6."""
    return cutoff * ALPHA * math.sqrt(math.pi / -math.log(1.0 - KEPT))


def mirror_tiled(z: np.ndarray) -> np.ndarray:
    """Heights `z` beside their reflections in x, in y and in both: a periodic 2n × 2m tile."""
    return np.block([[z, z[:, ::-1]], [z[::-1, :], z[::-1, ::-1]]])


def mirrored(topography):
    """A measured map made periodic by its mirror images: the map and its reflections in x, in y and in
    both, a periodic map of twice its side (no step where it repeats, unlike the map repeated as it
    is). A periodic BEM on it gives, at four times the load, four times the stiffness of the map's own
    area where the mirror images carry alike.

    **Arguments:** an areal SurfaceTopography map. **Returns:** the periodic `Topography`, 2n × 2m
    points over twice the sides, `info` kept.
    """
    z = np.asarray(topography.heights(), dtype=float)
    if z.ndim != 2:
        raise InputError("mirrored needs an areal map: a line scan has no second direction to mirror")
    tiled = mirror_tiled(z)
    sizes = tuple(2.0 * float(s) for s in topography.physical_sizes)
    return from_heights(tiled, sizes, periodic=True, info=dict(topography.info))


def lowest_roughness_q(topography) -> float | None:
    """The lowest wavevector (rad/m) a band may use on a roughness split off at a waviness cutoff
    (`info["waviness_cutoff"]`, set by `separate`); None for a measurement not split."""
    cutoff = topography.info.get("waviness_cutoff")
    return None if cutoff is None else 2.0 * math.pi / longest_roughness_wavelength(cutoff)


def separate(topography, form: AbstractForm = Curvature(), waviness_cutoff: float | None = None) -> Separated:
    """Remove a measurement's form and split its waviness from its roughness.

    **Arguments:**

    - `topography`: a SurfaceTopography line scan or map in metres (`read`, `areal_map`).
    - `form`: the form to remove, an `AbstractForm`: `Curvature()` (the default: the quadric that the
      spectrum's estimate removes too, so that a BEM on the heights and the models fitted to the
      spectrum see one surface), `Tilt()`, `Polynomial(degree)` or `Mean()`.
    - `waviness_cutoff`: λc, m: wavelengths longer than it go to the waviness (ISO 16610's Gaussian
      filter, half at λc). Between 8 grid spacings and the measurement's shorter side. None: no split.

    **Returns:** a `Separated`. **Raises:** `ValueError` naming `form` or `waviness_cutoff` and its valid
    range.
    """
    check_strategy("form", form, AbstractForm, FORMS, "jaxcontact.topography")
    sizes = tuple(float(s) for s in np.atleast_1d(topography.physical_sizes))
    grid = tuple(int(n) for n in np.atleast_1d(topography.nb_grid_pts))
    spacings = [s / n for s, n in zip(sizes, grid)]
    heights = np.asarray(topography.heights(), dtype=float)
    form_heights = form.heights(topography)
    rest = heights - form_heights
    waviness = np.zeros_like(rest)
    info = dict(topography.info)
    if waviness_cutoff is not None:
        low, high = 8 * max(spacings), min(sizes)
        if isinstance(waviness_cutoff, bool) or not (
            isinstance(waviness_cutoff, numbers.Real) and low <= waviness_cutoff <= high
        ):
            raise InputError(
                f"waviness_cutoff = {waviness_cutoff!r} m must lie in [{low:.3g}, {high:.3g}] m "
                "(8 grid spacings to the measurement's shorter side)"
            )
        ndimage = optional_import("scipy.ndimage", "splitting off the waviness")
        # ISO 16610-61's weighting exp(-π (r/(α λc))²) is a Gaussian of standard deviation α λc/√(2π).
        sigma = [ALPHA * waviness_cutoff / math.sqrt(2.0 * math.pi) / dx for dx in spacings]
        # A periodic map wraps round; a measured one is mirrored at its edges (no step there).
        waviness = ndimage.gaussian_filter(rest, sigma, mode="wrap" if topography.is_periodic else "reflect")
        rest = rest - waviness
        info["waviness_cutoff"] = float(waviness_cutoff)
    # The filter wraps round a periodic map, and a constant keeps it periodic; a tilt does not.
    periodic = topography.is_periodic and isinstance(form, Mean)
    info["separation"] = _removed(form, form_heights, waviness, waviness_cutoff, rest)
    roughness = from_heights(rest, sizes, periodic=periodic, info=info)
    return Separated(roughness, waviness, form_heights, form, waviness_cutoff)
