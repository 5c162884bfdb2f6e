"""The elastic boundary-element reference (docs/model.md §10), on ContactMechanics (the `bem` extra).

`bem_stiffness(topography, E, loads)` solves any areal map; `reference_curves(scene, loads)`
synthesises realisations of a scene's surface and reports their mean, spread and the grid's
convergence. Results are cached on disk (`ResultCache`).
"""

from ._cache import CacheWarning, ResultCache, default_directory
from ._solver import BEMResult, BEMSettings, bem_stiffness
from ._study import ReferenceCurves, realisation, reference_curves
from ._surfaces import check_grid, coarsened, synthesised_surface

__all__ = [
    "BEMResult",
    "BEMSettings",
    "CacheWarning",
    "ReferenceCurves",
    "ResultCache",
    "bem_stiffness",
    "check_grid",
    "coarsened",
    "default_directory",
    "realisation",
    "reference_curves",
    "synthesised_surface",
]
