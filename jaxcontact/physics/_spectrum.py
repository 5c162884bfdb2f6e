"""The power spectrum of the scene's surface, for the models that work from it (docs/model.md §8–9).

The W-M surface of the scene (D, G) is the isotropic self-affine surface whose line scans have
the W-M profile's spectrum: `C2D(q) = C0 q^-(6-2D)` in SurfaceTopography's convention
(`<h²> = (2π)^-2 ∫ C2D d²q`), with `C0 = K1 · 2√π Γ(3-D)/Γ(5/2-D)` and
`K1 = G^(2(D-1)) (2π)^(5-2D) / (4 ln γ)` (`jaxcontact.topography._conventions` derives both). It
spans `[q0, q1] = [2π/L, 2π/l_min]` with `L = sqrt(A_a)`.

Everything here is dimensionless (lengths in `L`, so `q0 = 2π`), in logs, and traceable in D and G.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
from jax.scipy.special import gammaln

from ..numerics import exponential_integral

W_M_GAMMA = 1.5  # the W-M series' frequency ratio γ (docs/model.md §8)
LOG_2PI = math.log(2.0 * math.pi)


def log_profile_prefactor(D, log_G):
    """`ln K1` of the W-M profile's `C1D(q) = K1 q^-(5-2D)`, `K1 = G^(2(D-1)) (2π)^(5-2D) / (4 ln γ)`
    (docs/model.md §8): arithmetic alone, for floats and arrays alike."""
    return 2.0 * (D - 1.0) * log_G + (5.0 - 2.0 * D) * LOG_2PI - math.log(4.0 * math.log(W_M_GAMMA))


def log_areal_prefactor(D, log_G, gammaln=gammaln):
    """`ln C0` of the isotropic map's `C2D(q) = C0 q^-(6-2D)` whose line scans are the W-M profile's
    (`C0 = K1 · 2 √π Γ(3-D) / Γ(5/2-D)`); in the scene's units (`log_G` = ln G*) it is `ln C0*`.
    `gammaln` JAX's by default; scipy's for host floats."""
    return log_profile_prefactor(D, log_G) + math.log(2.0 * math.sqrt(math.pi)) + gammaln(3.0 - D) - gammaln(2.5 - D)


def log_band(log_a_min):
    """`(ln q0*, ln q1*)`: the wavevectors of the nominal size `L` and of `l_min` (`l_min* = sqrt(a_min*)`)."""
    return jnp.full_like(log_a_min, LOG_2PI), LOG_2PI - 0.5 * log_a_min


def areal_moment(order: int, D, log_G, log_a_min):
    """`M_k = (1/2π) ∫_{q0}^{q1} q^(k+1) C2D(q) dq`: `<h²>` (k = 0), `<|∇h|²>` (k = 2), `<(∇²h)²>` (k = 4).

    A closed form (a power-law integral in `ln q`, exact through a zero exponent).
    """
    log_q0, log_q1 = log_band(log_a_min)
    log_coeff = log_areal_prefactor(D, log_G) - LOG_2PI
    return exponential_integral(log_coeff, order + 2.0 * D - 4.0, log_q0, log_q1)


def profile_moments(D, log_G, log_a_min):
    """Spectral moments `(m0, m2, m4)` of a line scan of the isotropic surface (McCool's `m_n`):
    `m0 = M_0`, `m2 = M_2/2`, `m4 = 3 M_4/8` (the averages of cos² and cos⁴ over directions).
    """
    return (
        areal_moment(0, D, log_G, log_a_min),
        areal_moment(2, D, log_G, log_a_min) / 2.0,
        areal_moment(4, D, log_G, log_a_min) * 3.0 / 8.0,
    )
