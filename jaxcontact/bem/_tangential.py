"""The tangential compliance of the half-space and the full-stick tangential stiffness of a contact set.

Two bodies of like material (Poisson's ratio ν): the normal and tangential problems uncouple
(Johnson 1985, §7.1), and a tangential traction q along x (the map's rows) displaces the surface
along x by the point Green's function `((1 + ν)/(π E)) ((1 − ν)/r + ν x²/r³)` (Johnson's Eq. 3.86a
for each body). In the grid units of `_operator` (pressure in `E* s_h/Δx`, `E* = E/(1 − ν²)` of the
pair) that is the normal compliance `1/(π r)` plus `ν/(1 − ν)` times `x²/(π r³)`:

- **periodic**: `û(q) = (2/|q|) (1 + ν/(1 − ν) · q_y²/|q|²)`, since the Fourier transform of
  `x²/r³` is `2π q_y²/|q|³`; averaged over directions the factor is `(2 − ν)/(2(1 − ν))`, the
  inverse of Mindlin's `8G*/(2E*)`;
- **free**: the pixel integral of `x²/r³` over a uniformly loaded square, in closed form from the
  antiderivative `y asinh(x/|y|)` (whose `∂²/∂x∂y` is `x²/r³`), added to Love's pixel kernel.

In full stick every point in contact (elastic or at the hardness cap) moves with the rigid body by
a common tangential displacement: the traction is `C_t,CC⁻¹ 1` times it on the contact set C, and
the stiffness is its sum, as `_tangent.elastic_stiffness` forms the normal unloading stiffness.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from ._operator import AbstractSubstrate, Compliance, Free


def shear_wavenumber(kx, ky, xp):
    """`(2/|q|) q_y²/|q|²` on the rfft2 grid (x along the rows), 0 at q = 0 (`_operator`'s wavenumbers)."""
    q2 = kx**2 + ky**2
    return xp.where(q2 > 0, 2.0 * ky**2 / xp.where(q2 > 0, q2, 1.0) ** 1.5, 0.0)


def pixel_anisotropy(x, y, xp=np):
    """`(1/π) ∫∫ s²/(s² + t²)^{3/2}` over the unit square centred on (x, y) (s along x), in grid
    spacings: the corners' alternating sum of `t asinh(s/|t|)`. Corners never have t = 0 for the
    integer centres of a grid."""

    def corner(s, t):
        return t * xp.arcsinh(s / xp.abs(t))

    a = 0.5
    total = corner(x + a, y + a) - corner(x - a, y + a) - corner(x + a, y - a) + corner(x - a, y - a)
    return total / math.pi


def tangential_compliance(normal: Compliance, substrate: AbstractSubstrate, nu) -> Compliance:
    """The tangential compliance (along the rows) beside the normal one, for Poisson's ratio `nu`
    (a JAX scalar in [0, 0.5), differentiable): the normal kernel plus `ν/(1 − ν)` times the
    anisotropic one."""
    n, fft, dtype = normal.n, normal.fft, normal.stiffness.dtype
    if isinstance(substrate, Free):
        anisotropy = fft.spatial_kernel(pixel_anisotropy, 2 * n, dtype)
    else:
        anisotropy = fft.spectral_kernel(shear_wavenumber, n, dtype)
    weight = jnp.asarray(nu / (1.0 - nu)).astype(anisotropy.dtype)  # a complex kernel (free) is written out as such
    kernel = normal.kernel + weight * anisotropy
    return Compliance(kernel, normal.stiffness, n, normal.fft)
