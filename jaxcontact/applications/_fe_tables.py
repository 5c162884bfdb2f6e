"""An `InterfaceLaw` written as finite-element codes read it: CalculiX's and Abaqus's tabular
pressure–overclosure block, and a CSV with the law's provenance."""

from __future__ import annotations

import numpy as np

from ..core import Scene
from ..numerics import InputError
from ._interface import InterfaceLaw


def provenance(scene: Scene, law: InterfaceLaw) -> list[str]:
    """What the law was computed from, one item per line: the model, the surface, the material, the
    nominal area and the closure's reference pressure (SI units)."""
    s, m = scene.surface, scene.material
    return [
        f"jaxcontact {_version()} interface law, model {scene.model.name}",
        f"surface D = {float(s.D):.6g}, G = {float(s.G):.6g} m, l_min = {float(s.l_min):.6g} m",
        f"material E = {float(m.E):.6g} Pa (contact modulus), nu = {float(m.nu):.6g}, H = {float(m.H):.6g} Pa",
        f"nominal area A_a = {float(law.nominal_area):.6g} m^2 (the law per unit area belongs to it)",
        f"closure measured from its value at the reference pressure p0 = {float(law.reference_pressure):.6g} Pa",
    ]


def pressure_overclosure(scene: Scene, law: InterfaceLaw) -> str:
    """The law as a `*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TABULAR` block (pressure in Pa, overclosure
    in m, ascending), which CalculiX and Abaqus read under a `*SURFACE INTERACTION`.

    The first row, `0, 0`, stands for the reference pressure p0: contact begins there, and the FE code
    extends the first segment's slope beyond the last row. Only points with status 0 above p0 are
    written; at least one is needed.

    **Arguments:** the `scene` the law was computed for (its provenance, written as `**` comments) and
    the `law`. **Returns:** the block's text.
    """
    rows = _rows_above_reference(law)
    lines = [f"** {line}" for line in provenance(scene, law)]
    lines.append("** the first row stands for p0 (contact begins there); pressure (Pa), overclosure (m)")
    lines.append("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TABULAR")
    lines.append("0., 0.")
    lines += [f"{p:.9e}, {d:.9e}" for p, d in rows]
    return "\n".join(lines) + "\n"


def interface_csv(scene: Scene, law: InterfaceLaw) -> str:
    """The law at every pressure as CSV (`#` provenance lines, then pressure_Pa, closure_m,
    normal_stiffness_Pa_per_m, contact_fraction, status)."""
    lines = [f"# {line}" for line in provenance(scene, law)]
    lines.append("pressure_Pa,closure_m,normal_stiffness_Pa_per_m,contact_fraction,status")
    for p, d, k, f, s in zip(*(np.asarray(getattr(law, name)) for name in InterfaceLaw.columns)):
        lines.append(f"{p:.9e},{d:.9e},{k:.9e},{f:.9e},{int(s)}")
    return "\n".join(lines) + "\n"


def _version() -> str:
    from importlib import metadata

    try:
        return metadata.version("jaxcontact")
    except metadata.PackageNotFoundError:  # run from a checkout that was not installed
        return "(not installed)"


def _rows_above_reference(law: InterfaceLaw) -> np.ndarray:
    p, d, status = (np.asarray(x) for x in (law.pressure, law.closure, law.status))
    p0 = float(law.reference_pressure)
    keep = (status == 0) & (p > p0)
    if not keep.any():
        raise InputError(
            f"no pressure above the reference p0 = {p0:g} Pa has status ok: an FE table needs at least one "
            "(give pressures above p0 within the model's range)"
        )
    order = np.argsort(p[keep])
    return np.stack([p[keep][order], d[keep][order]], axis=1)
