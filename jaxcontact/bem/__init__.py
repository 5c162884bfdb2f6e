"""The elastic boundary-element reference (docs/model.md §10).

`solve(heights, size, modulus, loads)` is the boundary-element contact in JAX: jit-compiled,
vmappable, differentiable, with an optional hardness cap; `solve_path` follows a load path on it,
the plastic flattening kept; `solve_layered` is the two-scale contact of a mesoscale gap with the
roughness a compliant layer (`WinklerLayer`, or a model's law as a `TabulatedLayer`).
`bem_stiffness(topography, E, loads)` solves the same problem with ContactMechanics (the `bem`
extra), the independent check; `reference_curves(scene, loads)` synthesises realisations of a
scene's surface and reports their mean, spread and the grid's convergence, cached on disk
(`ResultCache`).
"""

from ..models import register_model
from ._cache import CacheWarning, ResultCache, default_directory
from ._contact import ContactSolution, solve
from ._fft import AbstractFFT, DistributedFFT, LocalFFT
from ._layer import AbstractLayer, TabulatedLayer, WinklerLayer
from ._layered import LayeredSolution, solve_layered
from ._model import BEM
from ._operator import SUBSTRATES, AbstractSubstrate, Free, Periodic
from ._path import PathSolution, solve_path
from ._slip import FrictionLoops, friction_loops
from ._solver import BEMResult, BEMSettings, bem_stiffness
from ._study import REFERENCES, ReferenceCurves, jax_curve, realisation, reference_curves
from ._surfaces import check_grid, coarsened, synthesised_surface

__all__ = [
    "SUBSTRATES",
    "AbstractFFT",
    "AbstractLayer",
    "AbstractSubstrate",
    "BEM",
    "BEMResult",
    "BEMSettings",
    "CacheWarning",
    "DistributedFFT",
    "ContactSolution",
    "Free",
    "FrictionLoops",
    "LayeredSolution",
    "LocalFFT",
    "Periodic",
    "PathSolution",
    "REFERENCES",
    "ReferenceCurves",
    "ResultCache",
    "bem_stiffness",
    "check_grid",
    "coarsened",
    "default_directory",
    "friction_loops",
    "jax_curve",
    "realisation",
    "reference_curves",
    "solve",
    "solve_layered",
    "solve_path",
    "synthesised_surface",
    "TabulatedLayer",
    "WinklerLayer",
]

register_model(BEM)  # "bem" in scene files and `Scene(..., model="bem")`
