"""Interaction between asperities (Sec. 3) and the stiffness of one asperity (Eqs. 22–29).

The load `f` of an asperity, spread at the nominal pressure `P_m = F/A_a`, settles the
substrate under it by (Eq. 22)

    σ(a) = 1.12 √(f(a) P_m) / E          (1.12 ≈ 2/√π: centre of a uniformly loaded circle)

and the asperity's deformation is `ω = ξ ± σ`. The paper's Eqs. (23)–(26) print `ξ - σ`
(interaction "paper", which makes the joint *stiffer*, as its Fig. 6 shows); its conclusion (3)
says interaction lowers the stiffness, which is `ξ + σ` (interaction "series"). MODEL.md §3
offers both, and "none" (`ω = ξ`) as the comparator.

In dimensionless form (lengths in `sqrt(A_a)`, pressure in `E`) `σ* = 1.12 √(f* F*)`.
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from .powerlaw import PowerLaw

SETTLEMENT_COEFFICIENT = 1.12
INTERACTION_SIGNS = {"none": 0.0, "paper": -1.0, "series": 1.0}


def settlement(load_law: PowerLaw, log_load) -> PowerLaw:
    """Substrate settlement under an asperity, Eq. (22): `σ*(a) = 1.12 √(f*(a) P*)`, with `P* = F*`."""
    return (load_law.scaled(log_load)).sqrt().scaled(math.log(SETTLEMENT_COEFFICIENT))


def interaction_ratio(load_law: PowerLaw, interference_law: PowerLaw, log_load) -> PowerLaw:
    """`r(a) = σ'(a) / ξ'(a)`, so that `ω'(a) = ξ'(a) (1 ± r(a))`.

    Its exponent `(m + D)/2 - 1` is positive in every regime, so `r` grows with `a`.
    """
    return settlement(load_law, log_load).derivative() / interference_law.derivative()


def breakdown_log_area(ratio: PowerLaw):
    """`ln` of the area where `ω' = ξ' - σ'` vanishes (interaction "paper"): `r(a) = 1`.

    Closed form, since `r` is a power law in each regime. Past it, the paper's stiffness
    integrand `f'/ω'` has a pole and then changes sign: the model is no longer valid.
    """
    return -ratio.log_coeff / ratio.exponent


def stiffness_without_interaction(load_law: PowerLaw, interference_law: PowerLaw) -> PowerLaw:
    """Asperity stiffness with `ω = ξ`, Eqs. (27)–(29): `k(a) = f'(a) / ξ'(a)`."""
    return load_law.derivative() / interference_law.derivative()


def asperity_stiffness(load_law: PowerLaw, interference_law: PowerLaw, log_load, interaction: str, log_a):
    """Stiffness of one asperity, Eqs. (27)–(29): `k(a) = f'(a) / ω'(a)`, `ω = ξ ± σ`.

    **Arguments:**

    - `load_law`: the regime's `f(a)` (from `regime_load_laws`).
    - `interference_law`: `ξ(a)` (from `interference`).
    - `log_load`: `ln F*`, which sets the nominal pressure.
    - `interaction`: "none", "paper" or "series".
    - `log_a`: `ln(a / A_a)`.

    **Returns:** `k* = k / (E sqrt(A_a))`.
    """
    sign = INTERACTION_SIGNS[interaction]
    base = stiffness_without_interaction(load_law, interference_law)(log_a)
    if sign == 0.0:
        return base
    ratio = interaction_ratio(load_law, interference_law, log_load)(log_a)
    return base / (1.0 + sign * ratio)
