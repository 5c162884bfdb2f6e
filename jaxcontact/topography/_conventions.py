"""Spectra of the Weierstrass–Mandelbrot surface and the two conventions for its G (docs/model.md §8).

The model's G is the W-M amplitude of `z(x) = G^(D-1) Σ_n cos(2π γ^n x) / γ^((2-D) n)`, γ = 1.5,
whose profile PSD, in SurfaceTopography's convention (`<h²> = (1/π) ∫_0^∞ C1D dq`, q in rad/m), is
`C1D(q) = K1 q^-(5-2D)` with `K1 = G^(2(D-1)) (2π)^(5-2D) / (4 ln γ)`. The isotropic areal surface
with that line-scan PSD has `C2D(q) = C0 q^-(6-2D)`, `C0 = K1 · 2 √π Γ(3-D) / Γ(5/2-D)` (from
`C1D(qx) = (1/π) ∫_0^∞ C2D(√(qx² + qy²)) dqy = (C0/π) qx^-(5-2D) (√π/2) Γ(5/2-D)/Γ(3-D)`).

Papers that take G from the structure function `S(τ) = C G^(2(D-1)) τ^(4-2D)` with the commonly
quoted `C = Γ(2D-3) sin((2D-3)π/2) / ((4-2D) ln γ)` obtain `G_sf = (2π)^((2-D)/(D-1)) G`: the W-M
series' exact structure function is `(2π)^(4-2D)` times that.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from ..numerics._validate import InputError, assigned, check_range, spelled

GAMMA = 1.5
CONVENTIONS = ("wm", "structure-function")


def check_D(D):
    """D as a float array, after checking it lies in (1, 2)."""
    check_range("D", D, 1.0, 2.0)
    return np.asarray(D, dtype=float)


def check_positive(name, value, unit="m"):
    """Raise `InputError` naming `name` unless `value` (if given) is finite and > 0."""
    if value is not None and not (np.all(np.isfinite(value)) and np.all(np.asarray(value) > 0)):
        shown = spelled(repr(value), " ".join(f"{float(v):g}" for v in np.atleast_1d(value)))
        raise InputError(f"{assigned(name, shown)} {unit} must be finite and > 0 (valid range (0, inf) {unit})")


def convert_G(G, D, source: str = "wm", target: str = "structure-function"):
    """G in one convention → the other (`"wm"`, the model's own; `"structure-function"`).

    **Arguments:** `G` (m), `D` (1 < D < 2), `source` and `target` conventions.
    **Returns:** G in the `target` convention; `G_sf = (2π)^((2-D)/(D-1)) G_wm` (docs/model.md §8).
    """
    for name, value in (("source", source), ("target", target)):
        if value not in CONVENTIONS:
            raise InputError(f"{name} = {value!r} is not a G convention; valid: {', '.join(CONVENTIONS)}")
    D = check_D(D)
    check_positive("G", G)
    G = np.asarray(G, dtype=float)
    factor = (2.0 * math.pi) ** ((2.0 - D) / (D - 1.0))
    if source == target:
        return G
    return G * factor if target == "structure-function" else G / factor


def profile_prefactor(D, G):
    """`K1` of `C1D(q) = K1 q^-(5-2D)` (m^(2D-2)), for the W-M G."""
    return G ** (2 * (D - 1)) * (2 * math.pi) ** (5 - 2 * D) / (4 * math.log(GAMMA))


def areal_prefactor(D, G):
    """`C0` of the isotropic `C2D(q) = C0 q^-(6-2D)` whose line scans have `C1D = K1 q^-(5-2D)`."""
    return profile_prefactor(D, G) * 2 * math.sqrt(math.pi) * special.gamma(3 - D) / special.gamma(2.5 - D)


def structure_function_constant(D, convention: str = "wm"):
    """`C` of `S(τ) = <(z(x+τ) - z(x))²> = C G^(2(D-1)) τ^(4-2D)` for a G in `convention`."""
    # Γ(x) sin(πx/2) with x = 2D - 3, written as π / (2 Γ(1-x) cos(πx/2)) (reflection formula):
    # finite through D = 1.5, where Γ(x) alone is infinite.
    x = 2 * D - 3
    quoted = math.pi / (2 * special.gamma(1 - x) * np.cos(math.pi * x / 2)) / ((4 - 2 * D) * math.log(GAMMA))
    return quoted if convention == "structure-function" else quoted * (2 * math.pi) ** (4 - 2 * D)
