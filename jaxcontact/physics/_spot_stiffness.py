"""The stiffness of one contact spot, a choice of the `xia2024` model (docs/model.md §3, §9).

- `FamilyDerivative()` ("paper"): Eqs. (27)–(29), `k(a) = f'(a)/ξ'(a)`, the derivative along
  the Majumdar–Bhushan family of *different* asperities. In the elastic regime it is
  `(2π/3)(3-D)/(2-D)` times Sneddon's stiffness of one spot.
- `Sneddon()` ("sneddon"): `k(a) = 2E √(a/π)`, the stiffness of one circular spot of area `a` on
  an elastic half-space (Sneddon; Hertz), for every spot that is not fully plastic.

Either is then divided by `1 ± r` for the interaction readings (`physics._interaction`).
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp

from ..numerics import PowerLaw
from ._interaction import stiffness_without_interaction


def hertz_stiffness(like) -> PowerLaw:
    """Stiffness of one circular spot, `k = 2 E sqrt(a/π)`, in units of `E sqrt(A_a)`, shaped as `like`."""
    return PowerLaw(jnp.full_like(like, math.log(2.0) - 0.5 * math.log(math.pi)), jnp.full_like(like, 0.5))


class AbstractSpotStiffness(eqx.Module):
    """How one contact spot's stiffness follows from its load–area law; a choice of `Xia2024`."""

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def law(self, load_laws: PowerLaw, interference_law: PowerLaw) -> PowerLaw:
        """`k(a)` without interaction, one law per regime (shaped as `load_laws`)."""


class FamilyDerivative(AbstractSpotStiffness):
    """`k = f'(a)/ξ'(a)`, Eqs. (27)–(29) as the paper writes them (the default)."""

    name: ClassVar[str] = "paper"

    def law(self, load_laws, interference_law):
        return stiffness_without_interaction(load_laws, interference_law)


class Sneddon(AbstractSpotStiffness):
    """`k = 2E √(a/π)` for every spot (docs/model.md §9): the elastic regime's stiffness is the paper's
    divided by `(2π/3)(3-D)/(2-D)`."""

    name: ClassVar[str] = "sneddon"

    def law(self, load_laws, interference_law):
        del interference_law
        return hertz_stiffness(load_laws.log_coeff)
