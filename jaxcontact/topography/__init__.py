"""From a measured surface to D, G and l_min, with uncertainty (docs/model.md §8).

Reading and synthesis use SurfaceTopography (the `surface` extra: `pip install jaxcontact[surface]`).
"""

from ._characterise import METHODS, characterise
from ._checks import compared
from ._conventions import (
    CONVENTIONS,
    areal_prefactor,
    convert_G,
    log_prefactor,
    profile_prefactor,
    spectral_slope,
    structure_function_constant,
)
from ._psd import NoBandError
from ._read import read
from ._result import Characterisation
from ._stitch import characterise_stitched
from ._synthesis import areal_map, random_profile, wm_profile
from ._uncertainty import StiffnessBand, stiffness_band

__all__ = [
    "CONVENTIONS",
    "METHODS",
    "Characterisation",
    "NoBandError",
    "compared",
    "StiffnessBand",
    "areal_map",
    "areal_prefactor",
    "characterise",
    "characterise_stitched",
    "convert_G",
    "log_prefactor",
    "profile_prefactor",
    "random_profile",
    "read",
    "spectral_slope",
    "stiffness_band",
    "structure_function_constant",
    "wm_profile",
]
