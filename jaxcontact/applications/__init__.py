"""What is built on the stiffness: the load–approach curve, the interface law per unit area and the
tables FE codes read, a driven mass on the joint, sharded parameter sweeps, and chunked solves of
long load sweeps."""

from ._approach_sum import Approach, approach_quadrature, approach_star
from ._beam import lap_beam_frequency
from ._chunks import CHUNK, map_in_chunks, solve_sweep
from ._fe_tables import ansys_stiffness, interface_csv, pressure_overclosure, stick_friction
from ._interface import InterfaceLaw, interface_law
from ._path import LoadPath, solve_path
from ._sharded_sweep import SweepResult, sweep

# The applications that integrate with diffrax are imported when first used: diffrax's import
# (0.2 s beyond the equinox and optimistix that `solve` needs anyway) is not needed by `solve`
# or the command line's `run`.
_LAZY = {
    "Drive": "_dynamics",
    "Response": "_dynamics",
    "frequency_response": "_dynamics",
    "resonance_frequency": "_dynamics",
    "simulate": "_dynamics",
    "steady_amplitude": "_dynamics",
    "approach": "_loadapproach",
}

__all__ = [
    "Approach",
    "approach_quadrature",
    "approach_star",
    "InterfaceLaw",
    "LoadPath",
    "solve_path",
    "interface_law",
    "pressure_overclosure",
    "stick_friction",
    "ansys_stiffness",
    "interface_csv",
    "lap_beam_frequency",
    "SweepResult",
    "CHUNK",
    "map_in_chunks",
    "solve_sweep",
    "sweep",
    *_LAZY,
]


def __getattr__(name):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
