"""From a measured surface to D, G and l_min, with uncertainty (docs/model.md §8).

Reading and synthesis use SurfaceTopography (the `surface` extra: `pip install jaxcontact[surface]`).
"""

from ._characterise import METHODS, Characterisation, characterise
from ._conventions import CONVENTIONS, areal_prefactor, convert_G, profile_prefactor, structure_function_constant
from ._read import read
from ._synthesis import areal_map, random_profile, wm_profile
from ._uncertainty import StiffnessBand, stiffness_band

__all__ = [
    "CONVENTIONS",
    "METHODS",
    "Characterisation",
    "StiffnessBand",
    "areal_map",
    "areal_prefactor",
    "characterise",
    "convert_G",
    "profile_prefactor",
    "random_profile",
    "read",
    "stiffness_band",
    "structure_function_constant",
    "wm_profile",
]
