"""The default scene: the Table 1 grinding surface with the paper's material (docs/model.md §7).

Its one owner is the embedded scene file `scenes/table1_grinding.toml`, the default of the command
line; everything else (the stand-in of points with invalid parameters, the figures, the tests)
reads its values from here.
"""

from __future__ import annotations

import importlib.resources

from ..numerics import cached

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

DEFAULT_SCENE_FILE = "table1_grinding.toml"


@cached
def table1_values() -> dict[str, float]:
    """D, G, l_min (m), E, H (Pa), nu and area (m²) of the embedded default scene."""
    text = importlib.resources.files("jaxcontact").joinpath("scenes", DEFAULT_SCENE_FILE).read_text()
    data = tomllib.loads(text)
    values = {**data["surface"], **data["material"], **data["joint"]}
    return {k: float(v) for k, v in values.items()}


def table1_scene(model="xia2024", **options):
    """The Table 1 grinding scene as a `Scene`: `model` an object, or a name with its `options` by name."""
    from ..quantities import Material, Surface
    from ._scene import Scene

    v = table1_values()
    joint = Scene(Surface(D=v["D"], G=v["G"], l_min=v["l_min"]), Material(E=v["E"], nu=v["nu"], H=v["H"]), v["area"])
    return joint.with_model(model, **options)
