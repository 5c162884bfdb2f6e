"""jaxcontact: differentiable normal contact stiffness of rough mechanical joints.

The fractal model of Xia, Qu & Liu (Aerospace 11, 472, 2024) as specified in MODEL.md:
Kogut–Etsion asperity regimes over a Majumdar–Bhushan size distribution, with interaction
between asperities, solved under load control and differentiable end to end.

The package never enables float64 itself: call `jax.config.update("jax_enable_x64", True)`
for double precision (the command line does).
"""

from .approach import Approach, approach
from .asperity import REGIMES
from .distribution import wang_komvopoulos_psi
from .joint import AbstractJoint, JointResponse, Xia2024Joint
from .jzz2010 import JZZ2010Joint
from .parameters import Material, Surface
from .scene import INTERACTIONS, MODELS, Scene, stack_scenes
from .solution import Solution
from .solve import make_joint, solve
from .status import Status, status_message

__all__ = [
    "REGIMES", "INTERACTIONS", "MODELS",
    "Surface", "Material", "Scene", "Solution", "Status", "status_message",
    "solve", "approach", "Approach", "make_joint", "stack_scenes", "wang_komvopoulos_psi",
    "AbstractJoint", "JointResponse", "Xia2024Joint", "JZZ2010Joint",
]
__version__ = "0.1.0"
