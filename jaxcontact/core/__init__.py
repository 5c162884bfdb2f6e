"""The scene (the joint and its model), load control (`solve`, Sec. 4), its option (`Outputs`), the
`Solution`, and the default scene."""

from ._defaults import table1_scene, table1_values
from ._loadcontrol import dynamic_stiffness, kink_log_loads, point_solver, solve, tangential_stiffness
from ._prepare import prepare
from ._scene import Scene, stack_scenes
from ._settings import Outputs
from ._solution import Solution
from ._tangential import TangentialCycle, tangential_cycle

__all__ = [
    "dynamic_stiffness",
    "kink_log_loads",
    "Outputs",
    "point_solver",
    "prepare",
    "Scene",
    "Solution",
    "solve",
    "stack_scenes",
    "table1_scene",
    "table1_values",
    "tangential_stiffness",
    "TangentialCycle",
    "tangential_cycle",
]
