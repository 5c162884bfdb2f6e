"""What every layer shares: the joint's parameters (`Surface`, `Material`) and their valid ranges
(`PARAMETERS`), the units that make a scene dimensionless (`Scales`, `DimensionlessScene`), and the
per-point status codes (`Status`)."""

from ._domain import PARAMETERS, ParameterSpec, implausible
from ._pair import contact_modulus, tangential_contact_modulus
from ._parameters import Material, Surface
from ._scales import DimensionlessScene, Scales, nondimensionalise
from ._status import Branch, Status, StatusError, branches, status_message

__all__ = [
    "Branch",
    "branches",
    "DimensionlessScene",
    "implausible",
    "Material",
    "nondimensionalise",
    "PARAMETERS",
    "ParameterSpec",
    "Scales",
    "Status",
    "StatusError",
    "status_message",
    "Surface",
    "contact_modulus",
    "tangential_contact_modulus",
]
