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
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from ..numerics import cached
from ..numerics._compat import complex_dtype
from ..numerics._validate import optional_import
from ._fft import AbstractFFT, LocalFFT

# What ContactMechanics is imported for (the message naming the missing extra).
REFERENCE = "the boundary-element reference"


@cached
def _periodic_kernel(n: int) -> np.ndarray:
    """`2/|q|` on the rfft2 grid of an n × n map (q in rad per grid spacing), 0 at q = 0."""
    k = np.fft.fftfreq(n) * 2 * math.pi
    k_half = np.fft.rfftfreq(n) * 2 * math.pi
    q = np.sqrt(k[:, None] ** 2 + k_half[None, :] ** 2)
    with np.errstate(divide="ignore"):
        kernel = np.where(q > 0, 2.0 / q, 0.0)
    return kernel


@cached
def _free_kernel(n: int) -> np.ndarray:
    """The rfft2 of Love's pixel kernel on the 2n × 2n grid (ContactMechanics's `FreeFFTElasticHalfSpace`)."""
    a = b = 0.5
    i = np.arange(2 * n)
    x = np.where(i <= n, i, i - 2 * n).astype(float)[:, None]
    y = np.where(i <= n, i, i - 2 * n).astype(float)[None, :]

    def term(s, t, u, v):
        return s * np.log((t + np.sqrt(t * t + s * s)) / (u + np.sqrt(u * u + v * v)))

    real = (
        term(x + a, y + b, y - b, x + a)
        + term(y + b, x + a, x - a, y + b)
        + term(x - a, y - b, y + b, x - a)
        + term(y - b, x - a, x + a, y - b)
    ) / math.pi
    return np.fft.rfft2(real)


@cached
def _stiffness_kernel(n: int) -> np.ndarray:
    """`|q|/2` on the rfft2 grid of an n × n map, the periodic compliance's inverse, with the q = 0
    entry (where the compliance is 0) set to the smallest nonzero value, so that it is definite."""
    kernel = _periodic_kernel(n)
    inverse = np.where(kernel > 0, 1.0 / np.where(kernel > 0, kernel, 1.0), 0.0)
    inverse[0, 0] = 2 * math.pi / n / 2
    return inverse


class AbstractSubstrate(eqx.Module):
    """The elastic half-space under a map: how the map's edges are treated.

    **Class attributes:** `name` (reports, cache keys, the command line's `--substrate`), `padded`
    (whether the grid is doubled in each direction).
    """

    name: eqx.AbstractClassVar[str]
    padded: eqx.AbstractClassVar[bool]

    @abc.abstractmethod
    def kernel(self, n: int) -> np.ndarray:
        """The compliance's rfft2 kernel for an n × n map (grid units; 2n × 2n where `padded`)."""

    @abc.abstractmethod
    def reference(self, topography, modulus: float):
        """The same half-space in ContactMechanics (the independent reference, `bem_stiffness`)."""


class Periodic(AbstractSubstrate):
    """The map repeats: the point Green's function `2/(E |q|)`, with the q = 0 compliance zero
    (ContactMechanics's `PeriodicFFTElasticHalfSpace` with `stiffness_q0 = 0`)."""

    name: ClassVar[str] = "periodic"
    padded: ClassVar[bool] = False

    def kernel(self, n: int) -> np.ndarray:
        return _periodic_kernel(n)

    def reference(self, topography, modulus: float):
        cm = optional_import("ContactMechanics", REFERENCE)
        sizes = topography.physical_sizes
        return cm.PeriodicFFTElasticHalfSpace(topography.nb_grid_pts, modulus, physical_sizes=sizes, stiffness_q0=0.0)


class Free(AbstractSubstrate):
    """An isolated map on an infinite half-space: Love's pixel kernel on a grid doubled in each
    direction (ContactMechanics's `FreeFFTElasticHalfSpace`)."""

    name: ClassVar[str] = "free"
    padded: ClassVar[bool] = True

    def kernel(self, n: int) -> np.ndarray:
        return _free_kernel(n)

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
        stiffness = jnp.asarray(_stiffness_kernel(n), dtype)
        kernel = substrate.kernel(n)
        kernel_dtype = complex_dtype(dtype) if np.iscomplexobj(kernel) else dtype
        return cls(jnp.asarray(kernel, kernel_dtype), stiffness, n, fft)

    def inverse(self, displacement: Float[Array, "n n"]) -> Float[Array, "n n"]:
        """The periodic compliance's inverse (`|q|/2` by FFT, definite): exact for a periodic map in
        full contact, and the constrained iteration's preconditioner on its free set (either substrate)."""
        return self.fft.convolve(displacement, self.stiffness)

    def __call__(self, pressure: Float[Array, "n n"]) -> Float[Array, "n n"]:
        return self.fft.convolve(pressure, self.kernel)
