"""`jaxcontact interface`: the scene's interface law per unit area, written as the tables FE codes read."""

from __future__ import annotations

import pathlib

from ._output import CommandError, add_log_range, print_result

# Default pressures: F* = p/E from 1e-9 to 1e-4, the range of the paper's curves.
DEFAULT_PRESSURES_OVER_E = (1e-9, 1e-4)
FILES = ("interface.csv", "interface.inp", "interface.mac")


def cmd_interface(args) -> int:
    import numpy as np

    from ..applications import ansys_stiffness, interface_csv, interface_law, pressure_overclosure, stick_friction
    from ..quantities import status_message
    from ._report import format_table
    from ._scenefile import load_scene

    spec = load_scene(args.scene)
    scene = spec.scene
    E = float(scene.material.E)
    low, high = args.pressures or [f * E for f in DEFAULT_PRESSURES_OVER_E]
    if not 0 < low < high < float("inf"):
        raise CommandError(f"--pressures {low:g} {high:g} must be two pressures (Pa) with 0 < low < high")
    if args.points < 2:
        raise CommandError(f"--points {args.points} must be at least 2")
    reference = low if args.reference is None else args.reference
    if not 0 < reference <= high:
        raise CommandError(f"--reference {reference:g} must be a pressure (Pa) in (0, {high:g}]")
    law = interface_law(scene, np.geomspace(low, high, args.points), reference)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / FILES[0]).write_text(interface_csv(scene, law))
    table, friction_note = pressure_overclosure(scene, law), ", for CalculiX and Abaqus"
    if args.stick_pressure is not None and not 0 < args.stick_pressure < float("inf"):
        raise CommandError(f"--stick-pressure {args.stick_pressure:g} must be a pressure (Pa) > 0")
    stick = args.stick_pressure or _highest_with_stick(law)
    if args.friction is not None:
        if not 0 < args.friction < float("inf"):
            raise CommandError(f"--friction {args.friction:g} must be a friction coefficient > 0")
        if stick is None:
            raise CommandError(
                "no pressure of the law has a tangential stiffness: --friction needs one (see the table)"
            )
        table += stick_friction(scene, args.friction, stick)
        friction_note = (
            f" and *FRICTION (mu = {args.friction:g}, Mindlin's stick slope at {stick:g} Pa), for CalculiX; Abaqus "
            "reads the *FRICTION line otherwise"
        )
    (out / FILES[1]).write_text(table)
    if stick is None:
        ansys_note = "not written: no pressure of the law has a tangential stiffness"
    else:
        (out / FILES[2]).write_text(ansys_stiffness(scene, stick))
        ansys_note = f"ANSYS: FKN and FKT at {stick:g} Pa, absolute"
    from ._plots import plot_interface

    columns = {name: np.asarray(getattr(law, name)) for name in law.columns}
    figure = plot_interface(
        columns["pressure"], columns["closure"], columns["normal_stiffness"], reference, out / "interface.png"
    )
    files = [str(out / name) for name in FILES if (out / name).exists()] + [figure]
    rows = [
        {
            "p_Pa": float(p),
            "closure_m": float(d),
            "k_n_Pa_per_m": float(k),
            "k_n_dyn_Pa_per_m": float(k_dyn),
            "k_t_Pa_per_m": float(k_t),
            "contact_fraction": float(f),
            "status": status_message(int(s)) if s else "ok",
        }
        for p, d, k, k_dyn, k_t, f, s in zip(*(columns[name] for name in law.columns[:-1]))
    ]
    text = (
        f"{spec.title}: interface law per unit area (nominal area {float(scene.area):g} m², closure from "
        f"p0 = {reference:g} Pa)\n\n"
        + format_table(rows, ("p_Pa", "closure_m", "k_n_Pa_per_m", "k_n_dyn_Pa_per_m", "k_t_Pa_per_m", "status"))
        + "\n\n"
        + f"wrote {files[0]} (the law with its provenance)\n"
        + f"wrote {files[1]} (*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TABULAR{friction_note})\n"
        + (f"wrote {out / FILES[2]} ({ansys_note})\n" if stick is not None else f"{FILES[2]}: {ansys_note}\n")
        + f"wrote {figure}"
    )
    payload = {"title": spec.title, "nominal_area_m2": float(scene.area), "reference_pressure_Pa": reference}
    print_result(payload | {"rows": rows, "files": files}, args.format, text)
    return 0


def _highest_with_stick(law) -> float | None:
    """The highest pressure of the law with a tangential stiffness, or None where none has one."""
    import numpy as np

    ok = np.asarray(law.unloading_status) == 0
    return float(np.max(np.asarray(law.pressure)[ok])) if ok.any() else None


def add_interface_options(p) -> None:
    add_log_range(p, "pressures", "nominal pressures (Pa)", "1e-9 E to 1e-4 E", 40)
    p.add_argument("--reference", type=float, help="pressure (Pa) at which the closure is zero (default: LOW)")
    p.add_argument(
        "--friction",
        type=float,
        metavar="MU",
        help="add a *FRICTION block with this friction coefficient and Mindlin's full-stick slope k_t (Pa/m)",
    )
    p.add_argument(
        "--stick-pressure",
        type=float,
        metavar="P",
        help="nominal pressure (Pa) of the stick slope and of ANSYS's FKN/FKT, the preload's (default: the highest "
        "with a k_t)",
    )
