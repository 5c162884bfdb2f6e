"""From a measured surface to D, G and l_min, with uncertainty (docs/model.md §8).

Reading and synthesis use SurfaceTopography (the `surface` extra: `pip install jaxcontact[surface]`).
"""

from ._characterise import METHODS, characterise
from ._checks import compared
from ._conventions import (
    CONVENTIONS,
    areal_prefactor,
    convert_G,
    profile_prefactor,
    structure_function_constant,
)
from ._kind import AbstractKind, AbstractMeasurementKind, Areal, Profile, Stitched
from ._psd import NoBandError
from ._read import read
from ._result import Characterisation
from ._separate import AbstractForm, Curvature, Mean, Polynomial, Separated, Tilt, mirrored, separate
from ._stitch import characterise_stitched
from ._synthesis import areal_map, random_profile, wm_profile
from ._uncertainty import StiffnessBand, spectrum_band, stiffness_band

__all__ = [
    "CONVENTIONS",
    "AbstractForm",
    "AbstractKind",
    "Curvature",
    "Mean",
    "Polynomial",
    "Separated",
    "Tilt",
    "AbstractMeasurementKind",
    "Areal",
    "Profile",
    "Stitched",
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
    "profile_prefactor",
    "mirrored",
    "random_profile",
    "read",
    "separate",
    "spectrum_band",
    "stiffness_band",
    "structure_function_constant",
    "wm_profile",
]
