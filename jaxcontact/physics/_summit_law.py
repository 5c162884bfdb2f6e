"""How one spherical summit of radius R carries load at an interference ω (docs/model.md §9): a choice
of `MeasuredAsperities`.

- `HertzSummits()` ("hertz"): every summit elastic, `P = (4/3) E √R ω^(3/2)`, `A = π R ω`.
- `KogutEtsionSummits()` ("kogut-etsion"): the finite-element fits of Kogut & Etsion (J. Appl.
  Mech. 69, 657, 2002), as they apply them to Greenwood–Williamson summits (Tribol. Trans. 46, 383,
  2003). With `κ = 0.454 + 0.41ν` (the paper's Eq. 6), the critical interference, area and load
  `ω_c = (π κ H / (2E))² R`, `A_c = π R ω_c`, `P_c = (2/3) κ H A_c`:

  | band of ω/ω_c | P/P_c | A/A_c |
  |---|---|---|
  | [0, 1) | (ω/ω_c)^(3/2) (Hertz) | ω/ω_c |
  | [1, 6) | 1.03 (ω/ω_c)^1.425 | 0.93 (ω/ω_c)^1.136 |
  | [6, 110) | 1.40 (ω/ω_c)^1.263 | 0.94 (ω/ω_c)^1.146 |
  | [110, ∞) | H A / P_c (fully plastic) | 2 ω/ω_c |

  The fits are not continuous at the bands' ends (the load jumps by 3 %, 2 % and 8 % at ν = 0.3);
  a summit's initial unloading stiffness is Sneddon's `2E a` of its contact radius `a = √(A/π)` at
  the top (Etsion, Kligerman & Kadin, IJSS 42, 3716, 2005), fully plastic summits included.

Dimensionless as the scene is (lengths in `√A_a`, loads in `E A_a`, `H* = H/E`; E the composite
modulus). Both laws have the same four bands, so that a model's regimes do not depend on its law.
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import PowerLaw
from ._asperity import KOGUT_ETSION_BANDS, hardness_coefficient

SUMMIT_REGIMES = ("e", "ep1", "ep2", "p")


class SummitBands(eqx.Module):
    """A summit's load and contact area, a power law of the interference ω in each band.

    **Fields:** `edges`, ω at the bands' ends (0 first, ∞ last; ∞ also closes a band that is empty);
    `load`, `P(ω)`, and `area`, `A(ω)`, one law per band (`PowerLaw`s of `ln ω`).
    """

    edges: Float[Array, " edges"]
    load: PowerLaw
    area: PowerLaw

    def in_units(self, log_length) -> SummitBands:
        """The same laws with ω in units of `exp(log_length)` (loads and areas unchanged)."""
        scale = lambda law: law.scaled(law.exponent * log_length)  # noqa: E731
        return SummitBands(self.edges * jnp.exp(-log_length), scale(self.load), scale(self.area))

    def unloading_stiffness(self) -> PowerLaw:
        """A summit's initial unloading stiffness `2 √(A/π)` (Sneddon's `2E a`, E = 1)."""
        return self.area.scaled(-math.log(math.pi)).sqrt().scaled(math.log(2.0))

    def load_jumps(self) -> Float[Array, " inner"]:
        """How much a summit's load jumps where ω crosses each inner edge upwards (0 at an edge at ∞)."""
        inner = self.edges[1:-1]
        finite = jnp.isfinite(inner)
        log_edge = jnp.log(jnp.where(finite, inner, 1.0))
        jump = self.load[1:](log_edge) - self.load[:-1](log_edge)
        return jnp.where(finite, jump, 0.0)


class AbstractSummitLaw(eqx.Module):
    """How one summit carries load (module docstring); a choice of `MeasuredAsperities`.

    **Class attributes:** `name` (scene files, reports), `elastic` (whether a summit unloads along
    its loading curve), `bands_used` (how many of the four bands, from the first, can hold summits;
    the rest end at ∞)."""

    name: eqx.AbstractClassVar[str]
    elastic: eqx.AbstractClassVar[bool]
    bands_used: eqx.AbstractClassVar[int]

    @abc.abstractmethod
    def bands(self, log_R, log_hardness, nu) -> SummitBands:
        """The four bands' laws for summits of radius `exp(log_R)` (in `√A_a`), `ln(H/E)` and ν."""


def _hertz(log_R, like) -> tuple[PowerLaw, PowerLaw]:
    load = PowerLaw(jnp.full_like(like, math.log(4.0 / 3.0) + 0.5 * log_R), jnp.full_like(like, 1.5))
    area = PowerLaw(jnp.full_like(like, math.log(math.pi) + log_R), jnp.ones_like(like))
    return load, area


class HertzSummits(AbstractSummitLaw):
    """Every summit elastic (Hertz) at any interference, as Greenwood & Williamson (1966)."""

    name: ClassVar[str] = "hertz"
    elastic: ClassVar[bool] = True
    bands_used: ClassVar[int] = 1

    def bands(self, log_R, log_hardness, nu):
        del log_hardness, nu
        like = jnp.zeros((4,), jnp.result_type(log_R))
        load, area = _hertz(log_R, like)
        return SummitBands(jnp.concatenate([like[:1], jnp.full((4,), jnp.inf, like.dtype)]), load, area)


class KogutEtsionSummits(AbstractSummitLaw):
    """Kogut & Etsion's elastic–plastic summits (module docstring): elastic, two elastic–plastic
    bands, fully plastic; the hardness H and ν are the scene's material's."""

    name: ClassVar[str] = "kogut-etsion"
    elastic: ClassVar[bool] = False
    bands_used: ClassVar[int] = 4

    def bands(self, log_R, log_hardness, nu):
        dtype = jnp.result_type(log_R, log_hardness, nu)
        kappa = hardness_coefficient(jnp.asarray(nu, dtype))
        log_w_c = 2.0 * (jnp.log(0.5 * math.pi * kappa) + log_hardness) + log_R
        log_A_c = math.log(math.pi) + log_R + log_w_c
        log_P_c = jnp.log(2.0 / 3.0 * kappa) + log_hardness + log_A_c
        hertz_load, hertz_area = _hertz(log_R, jnp.zeros((1,), dtype))
        _, load_factor, load_exponent, area_factor, area_exponent = (
            jnp.asarray(c, dtype) for c in zip(*KOGUT_ETSION_BANDS)
        )
        plastic = math.log(2.0 * math.pi) + log_R  # A = 2πRω, P = H A
        load = PowerLaw(
            jnp.concatenate(
                [
                    hertz_load.log_coeff,
                    log_P_c + jnp.log(load_factor) - load_exponent * log_w_c,
                    (plastic + log_hardness)[None],
                ]
            ),
            jnp.concatenate([hertz_load.exponent, load_exponent, jnp.ones((1,), dtype)]),
        )
        area = PowerLaw(
            jnp.concatenate(
                [hertz_area.log_coeff, log_A_c + jnp.log(area_factor) - area_exponent * log_w_c, plastic[None]]
            ),
            jnp.concatenate([hertz_area.exponent, area_exponent, jnp.ones((1,), dtype)]),
        )
        ends = jnp.asarray([0.0, 1.0] + [end for end, *_ in KOGUT_ETSION_BANDS], dtype)
        # ∞ joined as a constant: ∞ · ω_c would give the derivatives with respect to ω_c a NaN.
        return SummitBands(jnp.concatenate([ends * jnp.exp(log_w_c), jnp.full((1,), jnp.inf, dtype)]), load, area)
