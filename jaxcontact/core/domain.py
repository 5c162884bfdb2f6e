"""The float parameters of a scene (MODEL.md §1): where each lives, its valid range, its units.

Declared once here and used everywhere a range matters: the checks when a `Surface`, `Material`
or `Scene` is built, the traced check that flags points whose parameters an optimiser moved out of
range (`loadcontrol.within_domain`), and the search bounds of `fitting`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import jax.numpy as jnp

from ..numerics.validate import check_range


@dataclasses.dataclass(frozen=True)
class ParameterSpec:
    """One float parameter of a scene.

    **Fields:** `name`; `meaning` and `unit` (for messages and tables); the valid range
    `low`..`high` with `low_open`/`high_open`; `get`, where it lives in a `Scene`; `log`, whether
    it is a positive scale (fitted and reported in logs); `search`, the range a fit explores by
    default (inside the valid range; finite, for the bounded reparameterisation).
    """

    name: str
    meaning: str
    unit: str
    low: float
    high: float
    get: Callable
    log: bool
    search: tuple[float, float]
    low_open: bool = True
    high_open: bool = True

    def check(self, value) -> None:
        """Raise `ValueError` (naming the parameter, its value and its range) for a concrete value outside it."""
        check_range(
            self.name,
            value,
            self.low,
            self.high,
            low_open=self.low_open,
            high_open=self.high_open,
            meaning=f"{self.meaning}, {self.unit}" if self.unit else self.meaning,
        )

    def contains(self, value):
        """Elementwise: whether a (possibly traced) value lies in the valid range."""
        above = (value > self.low) if self.low_open else (value >= self.low)
        below = (value < self.high) if self.high_open else (value <= self.high)
        return above & below


PARAMETERS: dict[str, ParameterSpec] = {
    p.name: p
    for p in (
        ParameterSpec("D", "fractal dimension", "", 1.0, 2.0, lambda s: s.surface.D, False, (1.0, 2.0)),
        ParameterSpec("G", "fractal roughness", "m", 0.0, math.inf, lambda s: s.surface.G, True, (1e-15, 1e-6)),
        ParameterSpec(
            "l_min", "lower cutoff length", "m", 0.0, math.inf, lambda s: s.surface.l_min, True, (1e-12, 1e-6)
        ),
        ParameterSpec(
            "E", "equivalent elastic modulus", "Pa", 0.0, math.inf, lambda s: s.material.E, True, (1e8, 1e13)
        ),
        ParameterSpec(
            "nu", "Poisson's ratio", "", 0.0, 0.5, lambda s: s.material.nu, False, (0.0, 0.5), low_open=False
        ),
        ParameterSpec("H", "hardness", "Pa", 0.0, math.inf, lambda s: s.material.H, True, (1e6, 1e12)),
        ParameterSpec("area", "nominal contact area", "m²", 0.0, math.inf, lambda s: s.area, True, (1e-10, 1.0)),
    )
}


def scene_fields(scene) -> tuple:
    """The scene's float parameters, ordered as `PARAMETERS`."""
    return tuple(p.get(scene) for p in PARAMETERS.values())


def inside_domain(scene):
    """Whether every float parameter of a (possibly traced) scene is valid, and `l_min² < area`."""
    values = dict(zip(PARAMETERS, scene_fields(scene)))
    inside = jnp.asarray(True)
    for name, spec in PARAMETERS.items():
        inside = inside & jnp.isfinite(values[name]) & spec.contains(values[name])
    return inside & (values["l_min"] * values["l_min"] < values["area"])
