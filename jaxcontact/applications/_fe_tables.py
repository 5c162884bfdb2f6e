"""An `InterfaceLaw` written as finite-element codes read it: CalculiX's and Abaqus's tabular
pressure–overclosure block, ANSYS's contact stiffnesses FKN and FKT at one pressure, and a CSV with
the law's provenance."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core import Scene, solve, tangential_stiffness
from ..models import MeasuredAsperities
from ..numerics import InputError, check_positive
from ..physics import MeasuredSpectrum
from ..quantities import status_message
from ._interface import InterfaceLaw


def provenance(scene: Scene, law: InterfaceLaw) -> list[str]:
    """What the law was computed from, one item per line: the model and its choices, the roughness
    it used, the material, the nominal area and the closure's reference pressure (SI units)."""
    m = scene.material
    choices = "".join(f", {key} {value}" for key, value in scene.model.options().items() if key != "model")
    return [
        f"jaxcontact {_version()} interface law, model {scene.model.name}{choices}",
        _roughness(scene),
        f"material E = {float(m.E):.6g} Pa (contact modulus), nu = {float(m.nu):.6g}, H = {float(m.H):.6g} Pa",
        f"nominal area A_a = {float(law.nominal_area):.6g} m^2 (the law per unit area belongs to it)",
        f"closure measured from its value at the reference pressure p0 = {float(law.reference_pressure):.6g} Pa",
    ]


def _roughness(scene: Scene) -> str:
    """The roughness the model reads: measured summits, a measured spectrum, or the surface's D, G, l_min."""
    model = scene.model
    if isinstance(model, MeasuredAsperities):
        heights = np.asarray(model.heights)
        return (
            f"measured summits R = {float(model.radius):.6g} m, density {float(model.density):.6g} 1/m^2, "
            f"height PDF on {heights.size} points over {heights[-1] - heights[0]:.6g} m"
        )
    fields = (getattr(model, field.name) for field in dataclasses.fields(model))
    spectrum = next((f for f in fields if isinstance(f, MeasuredSpectrum)), None)
    if spectrum is not None:
        q = np.exp(np.asarray(spectrum.log_q))
        return f"measured spectrum C2D on {q.size} wavenumbers, q = {q[0]:.6g} to {q[-1]:.6g} 1/m"
    s = scene.surface
    return f"surface D = {float(s.D):.6g}, G = {float(s.G):.6g} m, l_min = {float(s.l_min):.6g} m"


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


def stick_friction(scene: Scene, mu: float, pressure: float) -> str:
    """A `*FRICTION` block (CalculiX: `μ, λ`, λ the stick slope in Pa/m) whose λ is Mindlin's full-stick
    tangential stiffness per unit area at one nominal `pressure` (the preload's; it grows with the
    pressure), to follow the pressure–overclosure block under the same `*SURFACE INTERACTION`.

    **Arguments:** the `scene`, the friction coefficient `mu` (> 0) and the nominal `pressure` (Pa).
    **Returns:** the block's text. **Raises:** `ValueError` for a bad `mu` or `pressure`, or where the
    model gives no tangential stiffness at that pressure (its status says why).
    """
    if isinstance(mu, bool) or not (isinstance(mu, (int, float)) and 0 < mu < float("inf")):
        raise InputError(f"mu = {mu!r} must be a friction coefficient in (0, inf)")
    check_positive("pressure", pressure, "Pa", "pressure")
    k_t = _per_unit_area(scene, pressure, tangential_stiffness, "tangential stiffness")
    return (
        f"** Mindlin's full-stick slope (Pa/m) at the nominal pressure {pressure:.6g} Pa (docs/in-service.md)\n"
        f"*FRICTION\n{mu:.9g}, {k_t:.9e}\n"
    )


def _per_unit_area(scene: Scene, pressure: float, stiffness_of, what: str) -> float:
    """`stiffness_of(scene, loads)`'s stiffness per unit area (Pa/m) at the nominal `pressure`;
    `ValueError` naming `what` and the point's status where it has none."""
    solution = stiffness_of(scene, np.array([pressure * float(scene.area)]))
    status = int(solution.status[0])
    if status != 0:
        raise InputError(f"pressure = {pressure:g} Pa: no {what} there ({status_message(status)})")
    return float(solution.stiffness[0]) / float(scene.area)


# ANSYS's contact real constants by position (CONTA17x: R1, R2, FKN, FTOLN, ICONT, PINB, PMAX, PMIN,
# TAUMAX, CNOF, FKOP, FKT, ...); a negative value is an absolute stiffness (force/length³), not a factor.
_FKN, _FKT = 3, 12


def ansys_stiffness(scene: Scene, pressure: float) -> str:
    """APDL lines that set a contact pair's normal and tangential stiffness to the joint's at one
    nominal `pressure` (the preload's; both grow with it): `RMODIF` of FKN and FKT to minus k_n(p)
    (the loading tangent per unit area) and k_t(p) (Mindlin's full-stick slope per unit area), in
    Pa/m, which ANSYS reads as absolute values. The real-constant set is the parameter `JC_REAL`,
    set to 1 in the first line (edit it to the pair's).

    **Arguments:** the `scene` and the nominal `pressure` (Pa). **Raises:** `ValueError` for a bad
    `pressure`, or where the model gives no stiffness there (its status says why).
    """
    check_positive("pressure", pressure, "Pa", "pressure")
    k_n = _per_unit_area(scene, pressure, solve, "stiffness")
    k_t = _per_unit_area(scene, pressure, tangential_stiffness, "stiffness")
    s, m = scene.surface, scene.material
    return (
        f"! jaxcontact {_version()}, model {scene.model.name}: D = {float(s.D):.6g}, G = {float(s.G):.6g} m, "
        f"E = {float(m.E):.6g} Pa, A_a = {float(scene.area):.6g} m^2\n"
        f"! contact stiffnesses at the nominal pressure {pressure:.6g} Pa (negative: absolute, Pa/m)\n"
        "*SET,JC_REAL,1  ! the contact pair's real-constant set\n"
        f"RMODIF,JC_REAL,{_FKN},{-k_n:.9e}  ! FKN: k_n, the loading tangent per unit area\n"
        f"RMODIF,JC_REAL,{_FKT},{-k_t:.9e}  ! FKT: k_t, Mindlin's full-stick slope per unit area\n"
    )


# Each `InterfaceLaw.columns` field's CSV header.
CSV_HEADERS = {
    "pressure": "pressure_Pa",
    "closure": "closure_m",
    "normal_stiffness": "normal_stiffness_Pa_per_m",
    "dynamic_stiffness": "dynamic_stiffness_Pa_per_m",
    "tangential_stiffness": "tangential_stiffness_Pa_per_m",
    "contact_fraction": "contact_fraction",
    "status": "status",
    "unloading_status": "unloading_status",
}


def interface_csv(scene: Scene, law: InterfaceLaw) -> str:
    """The law at every pressure as CSV: `#` provenance lines, then a column per `InterfaceLaw.columns`
    field (pressure_Pa, closure_m, normal_stiffness_Pa_per_m, dynamic_stiffness_Pa_per_m,
    tangential_stiffness_Pa_per_m, contact_fraction, status, unloading_status)."""
    lines = [f"# {line}" for line in provenance(scene, law)]
    lines.append(",".join(CSV_HEADERS[name] for name in InterfaceLaw.columns))
    for row in zip(*(np.asarray(getattr(law, name)) for name in InterfaceLaw.columns)):
        lines.append(
            ",".join(str(int(x)) if "status" in name else f"{x:.9e}" for name, x in zip(InterfaceLaw.columns, row))
        )
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
