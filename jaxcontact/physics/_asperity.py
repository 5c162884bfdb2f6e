"""One asperity (Sec. 2): its geometry, its critical area and its load–area law in each regime.

Everything here is dimensionless: areas in units of the nominal area `A_a`, lengths in
`sqrt(A_a)`, loads in `E A_a` (so `G* = G / sqrt(A_a)` and `H* = H / E`). Areas enter as
`log_a = ln(a / A_a)`; each law is a `PowerLaw` in `a`.

The regimes are ordered as the paper orders them (Eqs. 15–18, 31–34): small asperities are
elastic, large ones plastic. Index 0..3 is e, ep1, ep2, p throughout the package.
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from ..numerics import PowerLaw

REGIMES = ("e", "ep1", "ep2", "p")

# Kogut–Etsion fits (J. Appl. Mech. 69, 657, 2002; the paper's Eqs. 8–11), one row per elastic–plastic
# band of ω/ω_c: (its end, load factor, load exponent β, area factor, area exponent α), with
# P/P_c = factor (ω/ω_c)^β and A/A_c = factor (ω/ω_c)^α; so f ∝ a^(β/α).
KOGUT_ETSION_BANDS = ((6.0, 1.03, 1.425, 0.93, 1.136), (110.0, 1.40, 1.263, 0.94, 1.146))
_EP1, _EP2 = KOGUT_ETSION_BANDS
EP1_LOAD_EXPONENT = _EP1[2] / _EP1[4]  # printed as 1.2544 in Eq. (12)
EP2_LOAD_EXPONENT = _EP2[2] / _EP2[4]  # printed as 1.1021 in Eq. (13)
EP1_END = _EP1[3] * _EP1[0] ** _EP1[4]  # a_epc / a_c, Eq. (17): printed 7.1197
EP2_END = _EP2[3] * _EP2[0] ** _EP2[4]  # a_pc / a_c, Eq. (18): printed 205.3827


def hardness_coefficient(nu):
    """κ = 0.454 + 0.41 ν, the paper's hardness coefficient "K" (Eq. 6)."""
    return 0.454 + 0.41 * nu


def log_critical_area(D, log_G, log_phi):
    """`ln a_c*`, Eq. (7): `a_c = G² φ^(2/(1-D))` with `φ = κH/(2E)`.

    Kept in logs: for D → 1 the power `2/(1-D)` makes `a_c` overflow any float.
    """
    return 2.0 * log_G + 2.0 * log_phi / (1.0 - D)


def kogut_etsion_laws(D, log_G, log_hardness, nu) -> tuple[PowerLaw, object]:
    """The four regimes' load laws (`regime_load_laws`) of a surface and material, and `ln a_c*`
    (Eq. 7, with `κ` of Eq. 6): what a Kogut–Etsion model needs of the dimensionless scene."""
    kappa = hardness_coefficient(jnp.asarray(nu))
    log_a_c = log_critical_area(D, log_G, jnp.log(kappa / 2.0) + log_hardness)  # φ = κH/(2E)
    return regime_load_laws(D, log_G, log_hardness, kappa, log_a_c), log_a_c


def interference(D, log_G) -> PowerLaw:
    """Total deformation (interference) of an asperity, Eq. (21): `ξ(a) = G^(D-1) a^((2-D)/2)`."""
    return PowerLaw(jnp.asarray((D - 1.0) * log_G), jnp.asarray((2.0 - D) / 2.0))


def regime_load_laws(D, log_G, log_hardness, kappa, log_a_c) -> PowerLaw:
    """Load–area laws `f(a)` of the four regimes, Eqs. (5), (12), (13), (19), as one `PowerLaw` of shape (4,).

    The Kogut–Etsion constants are computed from the fits rather than taken as printed
    (1.1282 = 1.03·0.93^(-m1), 0.2544 = m1 - 1, ...), so that nothing is rounded twice.

    **Arguments:**

    - `D`: fractal dimension.
    - `log_G`: `ln G*`.
    - `log_hardness`: `ln(H/E)`.
    - `kappa`: hardness coefficient κ.
    - `log_a_c`: `ln a_c*` from `log_critical_area`.

    **Returns:** a `PowerLaw` whose entries are the e, ep1, ep2 and p laws.
    """
    dtype = jnp.result_type(D, log_G, log_hardness, kappa, log_a_c)
    m1, m2 = EP1_LOAD_EXPONENT, EP2_LOAD_EXPONENT
    log_ep = jnp.log(2.0 / 3.0 * kappa) + log_hardness
    log_coeff = jnp.stack(
        [
            math.log(4.0 * math.sqrt(math.pi) / 3.0) + (D - 1.0) * log_G,  # Eq. (5), Hertz with MB interference
            log_ep + math.log(_EP1[1]) - m1 * math.log(_EP1[3]) + (1.0 - m1) * log_a_c,  # Eq. (12)
            log_ep + math.log(_EP2[1]) - m2 * math.log(_EP2[3]) + (1.0 - m2) * log_a_c,  # Eq. (13)
            jnp.broadcast_to(log_hardness, jnp.shape(log_a_c)),  # Eq. (19): f = H a
        ]
    ).astype(dtype)
    exponent = jnp.stack(jnp.broadcast_arrays((3.0 - D) / 2.0, m1, m2, 1.0)).astype(dtype)
    return PowerLaw(log_coeff, exponent)


def regime_edges(log_a_c):
    """`ln` of the regime boundaries 0, a_c, a_epc, a_pc, ∞ (Eqs. 7, 17, 18), shape (5,)."""
    inf = jnp.full_like(log_a_c, jnp.inf)
    return jnp.stack([-inf, log_a_c, log_a_c + math.log(EP1_END), log_a_c + math.log(EP2_END), inf])
