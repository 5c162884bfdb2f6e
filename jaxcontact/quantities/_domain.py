"""The float parameters of a scene (docs/model.md §1): where each lives, its valid range, its units.

Declared once here and used everywhere a range matters: the checks when a `Surface`, `Material`
or `Scene` is built, the traced check that flags points whose parameters an optimiser moved out of
range (`loadcontrol.within_domain`), and the search bounds of `fitting`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import operator
from collections.abc import Callable

import jax.numpy as jnp

from ..numerics._validate import check_range, concrete


@dataclasses.dataclass(frozen=True)
class ParameterSpec:
    """One float parameter of a scene.

    **Fields:** `name`; `meaning` and `unit` (for messages and tables); the valid range
    `low`..`high` with `low_open`/`high_open`; `get`, where it lives in a `Scene`; `log`, whether
    it is a positive scale (fitted and reported in logs); `search`, the range a fit explores by
    default (inside the valid range; finite, for the bounded reparameterisation); `typical`, the
    range engineering surfaces and materials have, outside which a value is more likely a unit
    mistake than a surface (`implausible`), with `unit_hint` naming the likely mistake.
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
    typical: tuple[float, float] | None = None
    unit_hint: str = ""

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

    @property
    def unit_suffix(self) -> str:
        """The unit as it follows a printed value (a space, then the unit); empty for a pure number."""
        return f" {self.unit}" if self.unit else ""

    def contains(self, value):
        """Elementwise: whether a (possibly traced) value lies in the valid range."""
        above = (value > self.low) if self.low_open else (value >= self.low)
        below = (value < self.high) if self.high_open else (value <= self.high)
        return above & below


PARAMETERS: dict[str, ParameterSpec] = {
    p.name: p
    for p in (
        ParameterSpec("D", "fractal dimension", "", 1.0, 2.0, lambda s: s.surface.D, False, (1.0, 2.0)),
        ParameterSpec(
            "G",
            "fractal roughness",
            "m",
            0.0,
            math.inf,
            lambda s: s.surface.G,
            True,
            (1e-15, 1e-6),
            typical=(1e-16, 1e-7),
            unit_hint="given in nm or µm instead of m?",
        ),
        ParameterSpec(
            "l_min",
            "lower cutoff length",
            "m",
            0.0,
            math.inf,
            lambda s: s.surface.l_min,
            True,
            (1e-12, 1e-6),
            typical=(1e-11, 1e-4),
            unit_hint="given in nm or µm instead of m?",
        ),
        ParameterSpec(
            "E",
            "equivalent elastic modulus",
            "Pa",
            0.0,
            math.inf,
            lambda s: s.material.E,
            True,
            (1e8, 1e13),
            typical=(1e8, 2e12),
            unit_hint="given in GPa or MPa instead of Pa?",
        ),
        ParameterSpec(
            "nu", "Poisson's ratio", "", 0.0, 0.5, lambda s: s.material.nu, False, (0.0, 0.5), low_open=False
        ),
        ParameterSpec(
            "H",
            "hardness",
            "Pa",
            0.0,
            math.inf,
            lambda s: s.material.H,
            True,
            (1e6, 1e12),
            typical=(1e7, 1e11),
            unit_hint="given in GPa or MPa instead of Pa?",
        ),
        ParameterSpec(
            "area",
            "nominal contact area",
            "m²",
            0.0,
            math.inf,
            lambda s: s.area,
            True,
            (1e-10, 1.0),
            typical=(1e-10, 1.0),
            unit_hint="given in mm² instead of m²?",
        ),
    )
}


def implausible(scene) -> list[str]:
    """Warnings for concrete parameters outside what engineering surfaces have (`typical`): a
    unit mistake, most likely. The model runs with them as they are; this only says so."""
    out = []
    for name, spec in PARAMETERS.items():
        value = concrete(spec.get(scene))
        if spec.typical is None or value is None or value.ndim != 0:
            continue
        low, high = spec.typical
        if not low <= float(value) <= high:
            out.append(
                f"{name} = {float(value):g} {spec.unit} is far outside what engineering surfaces have "
                f"({low:g}–{high:g} {spec.unit}): {spec.unit_hint} The model runs with it as it is."
            )
    return out


def scene_fields(scene) -> tuple:
    """The scene's float parameters, ordered as `PARAMETERS`."""
    return tuple(p.get(scene) for p in PARAMETERS.values())


def valid_fields(scene) -> dict:
    """Per float parameter of a (possibly traced) scene, whether it is valid; `l_min` and `area`
    also need `l_min² < area`."""
    values = dict(zip(PARAMETERS, scene_fields(scene)))
    valid = {name: jnp.isfinite(values[name]) & spec.contains(values[name]) for name, spec in PARAMETERS.items()}
    pair = values["l_min"] * values["l_min"] < values["area"]
    valid["l_min"], valid["area"] = valid["l_min"] & pair, valid["area"] & pair
    return valid


def all_valid(valid: dict):
    """Whether every parameter is valid, from `valid_fields`."""
    return functools.reduce(operator.and_, valid.values())
