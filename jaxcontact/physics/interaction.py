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
from typing import ClassVar

import equinox as eqx

from ..numerics.powerlaw import PowerLaw

SETTLEMENT_COEFFICIENT = 1.12


class AbstractInteraction(eqx.Module):
    """How the substrate settlement σ enters the asperity's deformation: `ω = ξ + sign · σ`.

    A choice, passed to a model as an object (`Xia2024(interaction=SeriesInteraction())`); it
    holds no arrays, so changing it compiles a different program and nothing is traced.
    """

    name: eqx.AbstractClassVar[str]
    sign: eqx.AbstractClassVar[float]


class NoInteraction(AbstractInteraction):
    """`ω = ξ`: the no-interaction comparator of the paper's Fig. 6."""

    name: ClassVar[str] = "none"
    sign: ClassVar[float] = 0.0


class PaperInteraction(AbstractInteraction):
    """`ω = ξ - σ`, Eqs. (23)–(26) as printed: a stiffer joint (Fig. 6), with a breakdown load."""

    name: ClassVar[str] = "paper"
    sign: ClassVar[float] = -1.0


class SeriesInteraction(AbstractInteraction):
    """`ω = ξ + σ`: settlement in series with the asperity, a softer joint (the paper's conclusion 3)."""

    name: ClassVar[str] = "series"
    sign: ClassVar[float] = 1.0


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
