"""Scene files: a TOML description of the joint, the loads and the effects wanted.

```toml
title = "..."
[surface]   D, G, l_min
[material]  E, nu, H
[joint]     area
[model]     name ("xia2024" | "jzz2010"), quadrature_nodes, max_steps
[effects]   interaction ("none" | "paper" | "series"), distribution ("mb" | "wk"), regime_shares (bool)
[loads]     unit ("N" | "F_star"), and either values = [...] or range = [lo, hi] with count
```

Effects are static: a scene that does not ask for one compiles a program without it
(`tests/test_effects.py` checks this on the traced program).
"""

from __future__ import annotations

import dataclasses
import importlib.resources
import math
import pathlib

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from .parameters import Material, Surface
from .scene import Scene

DEFAULT_SCENE = "table1_grinding.toml"

_SCHEMA = {
    "surface": {"D": float, "G": float, "l_min": float},
    "material": {"E": float, "nu": float, "H": float},
    "joint": {"area": float},
    "model": {"name": str, "quadrature_nodes": int, "max_steps": int},
    "effects": {"interaction": str, "distribution": str, "regime_shares": bool},
    "loads": {"unit": str, "values": list, "range": list, "count": int},
}
_REQUIRED = {"surface": ("D", "G"), "material": ("E", "nu", "H"), "joint": ("area",), "loads": ()}
MAX_LOADS = 10_000_000


class SceneFileError(ValueError):
    """A scene file that cannot be used; the message names the key, the value and what is allowed."""


@dataclasses.dataclass(frozen=True)
class SceneFile:
    """A scene as read from TOML: the `Scene`, the loads (N) and a title."""

    title: str
    scene: Scene
    loads: np.ndarray
    source: str

    @property
    def load_star(self) -> np.ndarray:
        return self.loads / (float(self.scene.material.E) * float(self.scene.area))


def _type_name(kind) -> str:
    return {float: "a number", int: "an integer", str: "a string", bool: "true or false", list: "a list"}[kind]


def _check_types(data: dict) -> None:
    for key in data:
        if key == "title":
            if not isinstance(data[key], str):
                raise SceneFileError(f"title = {data[key]!r} must be a string")
            continue
        if key not in _SCHEMA:
            raise SceneFileError(f"unknown table [{key}] (allowed: title, {', '.join(f'[{k}]' for k in _SCHEMA)})")
        if not isinstance(data[key], dict):
            raise SceneFileError(f"{key} must be a table [{key}], got {data[key]!r}")
        for name, value in data[key].items():
            allowed = _SCHEMA[key]
            if name not in allowed:
                raise SceneFileError(f"unknown key {key}.{name} (allowed in [{key}]: {', '.join(allowed)})")
            kind = allowed[name]
            ok = isinstance(value, kind) and not (kind in (int, float) and isinstance(value, bool))
            if kind is float:
                ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            if not ok:
                raise SceneFileError(f"{key}.{name} = {value!r} must be {_type_name(kind)}")
    for table, keys in _REQUIRED.items():
        if table not in data:
            raise SceneFileError(f"missing table [{table}]")
        for name in keys:
            if name not in data[table]:
                raise SceneFileError(f"missing key {table}.{name}")


def _loads(spec: dict, E: float, area: float) -> np.ndarray:
    unit = spec.get("unit", "N")
    if unit not in ("N", "F_star"):
        raise SceneFileError(f"loads.unit = {unit!r} is not one of 'N', 'F_star'")
    if ("values" in spec) == ("range" in spec):
        raise SceneFileError("[loads] needs exactly one of values = [...] or range = [low, high] (with count)")
    if "values" in spec:
        if "count" in spec:
            raise SceneFileError("loads.count goes with loads.range, not with loads.values")
        values = spec["values"]
        if not values or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            raise SceneFileError(f"loads.values = {values!r} must be a non-empty list of numbers")
        loads = np.asarray(values, dtype=float)
    else:
        bounds, count = spec["range"], spec.get("count", 21)
        if len(bounds) != 2 or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in bounds):
            raise SceneFileError(f"loads.range = {bounds!r} must be two numbers [low, high]")
        low, high = map(float, bounds)
        if not (0 < low <= high < math.inf):
            raise SceneFileError(f"loads.range = {bounds!r} must satisfy 0 < low <= high")
        if not 1 <= count <= MAX_LOADS:
            raise SceneFileError(f"loads.count = {count!r} must be in [1, {MAX_LOADS}]")
        loads = np.geomspace(low, high, count)
    bad = ~(np.isfinite(loads) & (loads > 0))
    if bad.any():
        raise SceneFileError(f"loads.values[{int(np.argmax(bad))}] = {float(loads[bad][0])!r} must be > 0 and finite")
    return loads * (E * area) if unit == "F_star" else loads


def parse_scene(data: dict, source: str = "<scene>") -> SceneFile:
    """Build a `SceneFile` from the parsed TOML dictionary."""
    _check_types(data)
    model = data.get("model", {})
    effects = data.get("effects", {})
    name = model.get("name", "xia2024")
    try:
        surface = Surface(**data["surface"])
        material = Material(**data["material"])
        options = {k: model[k] for k in ("quadrature_nodes", "max_steps") if k in model}
        interaction = effects.get("interaction", None)
        scene = Scene(surface, material, data["joint"]["area"], model=name, interaction=interaction,
                      distribution=effects.get("distribution", "mb"),
                      regime_shares=effects.get("regime_shares", True), **options)
    except SceneFileError:
        raise
    except ValueError as exc:
        raise SceneFileError(str(exc)) from None
    loads = _loads(data["loads"], float(material.E), float(scene.area))
    return SceneFile(title=data.get("title", pathlib.Path(source).stem), scene=scene, loads=loads, source=source)


def load_scene(path: str | pathlib.Path | None = None) -> SceneFile:
    """Read a scene file; with no path, the embedded default (Table 1 grinding surface)."""
    if path is None:
        text = importlib.resources.files("jaxcontact").joinpath("scenes", DEFAULT_SCENE).read_text()
        source = f"<embedded {DEFAULT_SCENE}>"
    else:
        path = pathlib.Path(path)
        if not path.is_file():
            raise SceneFileError(f"scene file {str(path)!r} does not exist")
        text, source = path.read_text(), str(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneFileError(f"{source} is not valid TOML: {exc}") from None
    return parse_scene(data, source)
