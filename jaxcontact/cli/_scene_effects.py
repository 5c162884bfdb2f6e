"""The scene file's effect tables that describe more than the joint: `[dynamics]` (a driven mass),
`[friction]` (the friction loops of `jaxcontact cycle`) and `[path]` (its normal load path),
checked as read."""

from __future__ import annotations

import dataclasses
import math

from ..numerics import InputError


class SceneFileError(InputError):
    """A scene file that cannot be used; the message names the key, the value and what is allowed."""


@dataclasses.dataclass(frozen=True)
class DynamicsSpec:
    """The `[dynamics]` table: the driven mass of `jaxcontact.applications` (`simulate`, `steady_amplitude`)."""

    mass: float
    preload: float
    amplitude: float
    damping_ratio: float | None = None
    damping: float | None = None
    frequency: float | None = None
    sweep: tuple[float, float] = (0.8, 1.2)
    sweep_count: int = 41


@dataclasses.dataclass(frozen=True)
class FrictionSpec:
    """The `[friction]` table: the friction coefficient and, optionally, the preload (N) and the
    range of tangential displacement amplitudes (m) of `jaxcontact cycle`."""

    mu: float
    preload: float | None = None
    amplitudes: tuple[float, float] | None = None


def friction_spec(spec: dict) -> FrictionSpec:
    mu = spec.get("mu")
    if mu is None:
        raise SceneFileError("missing key friction.mu (the friction coefficient)")
    if not (math.isfinite(mu) and mu > 0):
        raise SceneFileError(f"friction.mu = {mu!r} must be > 0")
    preload = spec.get("preload")
    if preload is not None and not (math.isfinite(preload) and preload > 0):
        raise SceneFileError(f"friction.preload = {preload!r} must be > 0 N")
    amplitudes = spec.get("amplitudes")
    if amplitudes is not None:
        ok = len(amplitudes) == 2 and all(isinstance(x, (int, float)) and math.isfinite(x) for x in amplitudes)
        if not ok or not 0 < amplitudes[0] < amplitudes[1]:
            raise SceneFileError(f"friction.amplitudes = {amplitudes!r} must be [low, high] (m) with 0 < low < high")
        amplitudes = (float(amplitudes[0]), float(amplitudes[1]))
    return FrictionSpec(float(mu), None if preload is None else float(preload), amplitudes)


def path_spec(spec: dict) -> tuple[float, ...]:
    """The `[path]` table's `loads`: a load path (N) in the order applied, at least two loads > 0."""
    loads = spec.get("loads")
    if loads is None:
        raise SceneFileError("missing key path.loads (the loads, N, in the order applied)")
    ok = len(loads) >= 2 and all(isinstance(x, (int, float)) and math.isfinite(x) and x > 0 for x in loads)
    if not ok:
        raise SceneFileError(f"path.loads = {loads!r} must be at least two loads (N), each > 0, in the order applied")
    return tuple(float(x) for x in loads)


def dynamics_spec(spec: dict) -> DynamicsSpec:
    for key in ("mass", "preload", "amplitude"):
        if key not in spec:
            raise SceneFileError(f"missing key dynamics.{key}")
        if not spec[key] > 0:
            raise SceneFileError(f"dynamics.{key} = {spec[key]!r} must be > 0")
    if not spec["amplitude"] < spec["preload"]:
        raise SceneFileError(
            f"dynamics.amplitude = {spec['amplitude']!r} N must be smaller than dynamics.preload = "
            f"{spec['preload']!r} N (a larger amplitude would open the joint)"
        )
    if ("damping_ratio" in spec) == ("damping" in spec):
        raise SceneFileError("[dynamics] needs exactly one of damping_ratio (ζ) or damping (N s/m)")
    for key in ("damping_ratio", "damping"):
        if key in spec and not spec[key] >= 0:
            raise SceneFileError(f"dynamics.{key} = {spec[key]!r} must be >= 0")
    if "frequency" in spec and not spec["frequency"] > 0:
        raise SceneFileError(f"dynamics.frequency = {spec['frequency']!r} must be > 0 Hz")
    sweep = spec.get("sweep", [0.8, 1.2])
    if len(sweep) != 2 or not all(isinstance(v, (int, float)) for v in sweep) or not 0 < sweep[0] < sweep[1]:
        raise SceneFileError(
            f"dynamics.sweep = {sweep!r} must be [low, high] with 0 < low < high "
            "(multiples of the linear resonance frequency)"
        )
    count = spec.get("sweep_count", 41)
    if not 2 <= count <= 10_000:
        raise SceneFileError(f"dynamics.sweep_count = {count!r} must be in [2, 10000]")
    return DynamicsSpec(
        mass=float(spec["mass"]),
        preload=float(spec["preload"]),
        amplitude=float(spec["amplitude"]),
        damping_ratio=spec.get("damping_ratio"),
        damping=spec.get("damping"),
        frequency=spec.get("frequency"),
        sweep=(float(sweep[0]), float(sweep[1])),
        sweep_count=count,
    )
