"""Scene files: a TOML description of the joint, the loads and the effects wanted.

```toml
title = "..."
[surface]   D, G, l_min
[material]  E, nu, H
[joint]     area
[model]     name ("xia2024" | "jzz2010" | "gw" | "persson"), and every option `Scene` takes:
            interaction ("none" | "paper" | "series"), distribution ("mb" | "wk"),
            spot_stiffness ("paper" | "sneddon"), quadrature ("power-series" | "gauss-legendre" |
            "adaptive"), quadrature_nodes, quadrature_tolerance, max_steps, solver_tolerance
[effects]   interaction, distribution, spot_stiffness (here or in [model]), regime_shares (bool),
            stiffness ("loading" | "unloading" | "tangential": which K `solve` returns)
[loads]     unit ("N" | "F_star"), and either values = [...] or range = [lo, hi] with count
[approach]  reference_load (N): ask for the load–approach curve relative to this preload
[friction]  mu (coefficient), preload (N), amplitudes = [lo, hi] (m): the friction loops of `jaxcontact cycle`
[path]      loads = [F1, F2, ...] (N, in the order applied): the normal load path of `jaxcontact cycle`
[dynamics]  mass (kg), preload (N), amplitude (N), damping_ratio (ζ) or damping (N s/m),
            frequency (Hz; default the linear resonance), sweep = [lo, hi] (× resonance), sweep_count
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

from ..core import Outputs, Scene
from ..numerics import InputError
from ..numerics._validate import decoded_text, file_spelling
from ..quantities import Material, Scales, Surface
from ._scene_effects import DynamicsSpec, FrictionSpec, SceneFileError, dynamics_spec, friction_spec, path_spec

DEFAULT_SCENE = "table1_grinding.toml"

_SCHEMA = {
    "surface": {"D": float, "G": float, "l_min": float},
    "material": {"E": float, "nu": float, "H": float},
    "joint": {"area": float},
    "model": {
        "name": str,
        "interaction": str,
        "distribution": str,
        "spot_stiffness": str,
        "quadrature": str,
        "quadrature_nodes": int,
        "quadrature_tolerance": float,
        "max_steps": int,
        "solver_tolerance": float,
    },
    "effects": {
        "interaction": str,
        "distribution": str,
        "spot_stiffness": str,
        "regime_shares": bool,
        "stiffness": str,
    },
    "loads": {"unit": str, "values": list, "range": list, "count": int},
    "approach": {"reference_load": float},
    "friction": {"mu": float, "preload": float, "amplitudes": list},
    "path": {"loads": list},
    "dynamics": {
        "mass": float,
        "preload": float,
        "amplitude": float,
        "damping_ratio": float,
        "damping": float,
        "frequency": float,
        "sweep": list,
        "sweep_count": int,
    },
}
_REQUIRED = {"surface": ("D", "G"), "material": ("E", "nu", "H"), "joint": ("area",), "loads": ()}
DYNAMICS_SCENE = "table1_dynamics.toml"
MAX_LOADS = 10_000_000


@dataclasses.dataclass(frozen=True)
class SceneFile:
    """A scene as read from TOML: the `Scene`, the loads (N), a title, the optional effects
    `approach_reference` (N, the preload of the load–approach curve), `dynamics`, `friction` and
    `path` (N, a load path in the order applied), and the option of `solve` it asks for
    (`outputs`: `[effects] regime_shares`). `[model] max_steps` and `solver_tolerance` are the
    model's root finder (`NewtonBisection`)."""

    title: str
    scene: Scene
    loads: np.ndarray
    source: str
    approach_reference: float | None = None
    dynamics: DynamicsSpec | None = None
    outputs: Outputs = Outputs()
    friction: FrictionSpec | None = None
    path: tuple[float, ...] | None = None

    @property
    def load_star(self) -> np.ndarray:
        return self.loads / float(Scales.of(self.scene).load)


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
            # TOML booleans are ints to Python; an integer is a fine float.
            accepted = (int, float) if kind is float else kind
            if not isinstance(value, accepted) or (kind is not bool and isinstance(value, bool)):
                raise SceneFileError(f"{key}.{name} = {value!r} must be {_type_name(kind)}")
    for table, keys in _REQUIRED.items():
        if table not in data:
            raise SceneFileError(f"missing table [{table}]")
        for name in keys:
            if name not in data[table]:
                raise SceneFileError(f"missing key {table}.{name}")


def _loads(spec: dict, load_unit: float) -> np.ndarray:
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
    return loads * load_unit if unit == "F_star" else loads


# The [effects] keys that are options of `solve` (`Outputs`), not of the model.
OUTPUT_OPTIONS = ("regime_shares", "stiffness")


def stiffness_of(name: str | None):
    """The `AbstractStiffness` a scene file or the command line names ("loading" by default)."""
    from ..core._settings import STIFFNESSES

    if name is None:
        return STIFFNESSES["loading"]()
    if name not in STIFFNESSES:
        raise InputError(f"stiffness = {name!r} must be one of {', '.join(map(repr, STIFFNESSES))}")
    return STIFFNESSES[name]()


def parse_scene(data: dict, source: str = "<scene>") -> SceneFile:
    """Build a `SceneFile` from the parsed TOML dictionary."""
    _check_types(data)
    model = dict(data.get("model", {}))
    effects = data.get("effects", {})
    name = model.pop("name", "xia2024")
    for key in set(model) & set(effects):
        raise SceneFileError(f"{key} is given in both [model] and [effects]: give it once")
    options = {**model, **{k: v for k, v in effects.items() if k not in OUTPUT_OPTIONS}}
    try:
        with file_spelling():
            surface = Surface(**data["surface"])
            material = Material(**data["material"])
            scene = Scene(surface, material, data["joint"]["area"], model=name, **options)
            outputs = Outputs(
                regime_shares=effects.get("regime_shares", True), stiffness=stiffness_of(effects.get("stiffness"))
            )
    except SceneFileError:
        raise
    except InputError as exc:
        raise SceneFileError(str(exc)) from None
    loads = _loads(data["loads"], float(Scales.of(scene).load))
    reference = data.get("approach", {}).get("reference_load")
    if "approach" in data:
        if reference is None:
            raise SceneFileError("missing key approach.reference_load (the preload, N, where the approach is zero)")
        if not (math.isfinite(reference) and reference > 0):
            raise SceneFileError(f"approach.reference_load = {reference!r} must be > 0 N")
    return SceneFile(
        title=data.get("title", pathlib.Path(source).stem),
        scene=scene,
        loads=loads,
        source=source,
        approach_reference=None if reference is None else float(reference),
        dynamics=dynamics_spec(data["dynamics"]) if "dynamics" in data else None,
        outputs=outputs,
        friction=friction_spec(data["friction"]) if "friction" in data else None,
        path=path_spec(data["path"]) if "path" in data else None,
    )


def load_scene(path: str | pathlib.Path | None = None, default: str = DEFAULT_SCENE) -> SceneFile:
    """Read a scene file; with no path, an embedded one (`default`: the Table 1 grinding surface)."""
    if path is None:
        text = importlib.resources.files("jaxcontact").joinpath("scenes", default).read_text()
        source = f"<embedded {default}>"
    else:
        path = pathlib.Path(path)
        if path.is_dir():
            raise SceneFileError(f"scene file {str(path)!r} is a directory, not a TOML file")
        if not path.is_file():
            raise SceneFileError(f"scene file {str(path)!r} does not exist")
        text, source = decoded_text(path.read_bytes())[0], str(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneFileError(f"{source} is not valid TOML: {exc}") from None
    return parse_scene(data, source)
