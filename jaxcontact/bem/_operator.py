"""The elastic half-space's compliance on a grid: surface displacement from surface pressure, by FFT.

Grid units: lengths in grid spacings Δx, heights and displacements in a height scale s_h, pressure
in `E s_h / Δx` (E the contact modulus). Then `u = C p` has no parameter left, and float32 works.
The discretisation is ContactMechanics's (docs/model.md §10), so that the two agree:

- **periodic**: the point Green's function in Fourier space, `û(q) = 2 p̂(q) / (E |q|)`, with the
  q = 0 compliance set to zero (`stiffness_q0 = 0`: the mean displacement is not fixed, and the
  offset is minus the change of the mean separation);
- **free**: Love's displacement at pixel centres from a uniform pressure on each square pixel
  (Johnson 1985, Eq. 3.25), applied by FFT on a grid doubled in each direction (zero padding), so
  that the map is an isolated patch on an infinite half-space.
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
from jaxtyping import Array, Complex, Float

from ..numerics._validate import optional_import
from ._fft import AbstractFFT, LocalFFT

# What ContactMechanics is imported for (the message naming the missing extra).
REFERENCE = "the boundary-element reference"


# The kernels as functions of the wavenumbers (rad per grid spacing: a column `kx` over every row of
# the rfft2 grid, a row `ky` over its columns) or of the pixel offsets (`x`, `y`, on the transform's
# whole grid), in the array namespace `xp`: numpy on one device, jax.numpy on each device's share
# (`_fft`).


def inverse_wavenumber(kx, ky, xp):
    """`2/|q|`, the periodic compliance's point Green's function, 0 at q = 0."""
    q = xp.sqrt(kx**2 + ky**2)
    return xp.where(q > 0, 2.0 / xp.where(q > 0, q, 1.0), 0.0)


def half_wavenumber(kx, ky, xp):
    """`|q|/2`, the periodic compliance's inverse, with the q = 0 entry (where the compliance is 0)
    set to the smallest nonzero value, so that it is definite."""
    compliance = inverse_wavenumber(kx, ky, xp)
    smallest = 2 * math.pi / kx.shape[0] / 2
    return xp.where(compliance > 0, 1.0 / xp.where(compliance > 0, compliance, 1.0), smallest)


def love_pixel(x, y, xp):
    """Love's displacement at offset (x, y) from a unit pressure on a unit square pixel (Johnson 1985,
    Eq. 3.25, over π), in grid spacings (ContactMechanics's `FreeFFTElasticHalfSpace`)."""
    a = b = 0.5

    def term(s, t, u, v):
        return s * xp.log((t + xp.sqrt(t * t + s * s)) / (u + xp.sqrt(u * u + v * v)))

    return (
        term(x + a, y + b, y - b, x + a)
        + term(y + b, x + a, x - a, y + b)
        + term(x - a, y - b, y + b, x - a)
        + term(y - b, x - a, x + a, y - b)
    ) / math.pi


class AbstractSubstrate(eqx.Module):
    """The elastic half-space under a map: how the map's edges are treated.

    **Class attributes:** `name` (reports, cache keys, the command line's `--substrate`).
    """

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def kernel(self, n: int, fft: AbstractFFT, dtype):
        """The compliance's kernel for an n × n map (grid units), in `fft`'s layout."""

    @abc.abstractmethod
    def reference(self, topography, modulus: float):
        """The same half-space in ContactMechanics (the independent reference, `bem_stiffness`)."""


class Periodic(AbstractSubstrate):
    """The map repeats: the point Green's function `2/(E |q|)`, with the q = 0 compliance zero
    (ContactMechanics's `PeriodicFFTElasticHalfSpace` with `stiffness_q0 = 0`)."""

    name: ClassVar[str] = "periodic"

    def kernel(self, n: int, fft: AbstractFFT, dtype):
        return fft.spectral_kernel(inverse_wavenumber, n, dtype)

    def reference(self, topography, modulus: float):
        cm = optional_import("ContactMechanics", REFERENCE)
        sizes = topography.physical_sizes
        return cm.PeriodicFFTElasticHalfSpace(topography.nb_grid_pts, modulus, physical_sizes=sizes, stiffness_q0=0.0)


class Free(AbstractSubstrate):
    """An isolated map on an infinite half-space: Love's pixel kernel on a grid doubled in each
    direction (ContactMechanics's `FreeFFTElasticHalfSpace`)."""

    name: ClassVar[str] = "free"

    def kernel(self, n: int, fft: AbstractFFT, dtype):
        return fft.spatial_kernel(love_pixel, 2 * n, dtype)

    def reference(self, topography, modulus: float):
        cm = optional_import("ContactMechanics", REFERENCE)
        return cm.FreeFFTElasticHalfSpace(topography.nb_grid_pts, modulus, physical_sizes=topography.physical_sizes)


# The command line's names.
SUBSTRATES = {"periodic": Periodic, "free": Free}


class Compliance(eqx.Module):
    """`u = C p` on an n × n grid (grid units above), periodic or free, its FFTs laid out by `fft`
    (`_fft`). Symmetric positive semidefinite (definite for "free"; for "periodic" its null space is
    the constant pressure)."""

    kernel: Complex[Array, "rows columns"] | Float[Array, "rows columns"]
    stiffness: Float[Array, "n half"]
    n: int = eqx.field(static=True)
    fft: AbstractFFT = LocalFFT()

    @classmethod
    def build(cls, n: int, substrate: AbstractSubstrate, dtype, fft: AbstractFFT = LocalFFT()) -> Compliance:
        stiffness = fft.spectral_kernel(half_wavenumber, n, dtype)
        return cls(substrate.kernel(n, fft, dtype), stiffness, n, fft)

    def inverse(self, displacement: Float[Array, "n n"]) -> Float[Array, "n n"]:
        """The periodic compliance's inverse (`|q|/2` by FFT, definite): exact for a periodic map in
        full contact, and the constrained iteration's preconditioner on its free set (either substrate)."""
        return self.fft.convolve(displacement, self.stiffness)

    def __call__(self, pressure: Float[Array, "n n"]) -> Float[Array, "n n"]:
        return self.fft.convolve(pressure, self.kernel)
