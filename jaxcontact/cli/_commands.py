"""The commands of `jaxcontact`: each reads a scene (or data), runs the library, writes files and
prints a table or JSON. User mistakes raise `CommandError` (or `ValueError`), reported in one line.
"""

from __future__ import annotations

import dataclasses
import pathlib

from ._output import CommandError, implausible_values, print_result


def cmd_run(args) -> int:
    import numpy as np

    from ..applications import solve_sweep
    from ._report import flagged_summary, format_table, record_comments, scene_record, solution_rows, write_csv
    from ._scenefile import load_scene

    spec = load_scene(args.scene)
    band, others, notes = None, {}, []
    if getattr(args, "topography", None):
        from ._topography_run import topography_run

        spec, band, others, notes = topography_run(spec, args)
    elif args.command == "run":
        from ._topography_run import overridden

        spec = overridden(spec, args)
    if getattr(args, "stiffness", None):
        from ._scenefile import stiffness_of

        outputs = dataclasses.replace(spec.outputs, stiffness=stiffness_of(args.stiffness))
        spec = dataclasses.replace(spec, outputs=outputs)
    if spec.outputs.stiffness.name != "loading":
        notes.insert(0, f"K is the {STIFFNESS_WORDS[spec.outputs.stiffness.name]} (docs/in-service.md)")
    if spec.scene.model.name == "bem":
        # A grid that cannot resolve l_min flags every load: refused before the solves, as `compare` does.
        from ..bem import check_grid
        from ..numerics import InputError

        scene = spec.scene
        try:
            check_grid(float(scene.surface.l_min), float(scene.area) ** 0.5, scene.model.grid)
        except InputError as exc:
            raise InputError(f"{exc} (the grid is the scene file's [model] grid)") from None
    warnings = implausible_values(spec)
    solution = solve_sweep(
        spec.scene,
        spec.loads,
        outputs=spec.outputs,
        progress=args.progress and spec.loads.size > 4096,
    )
    rows = solution_rows(solution)
    if band is not None:
        from ..quantities import status_message
        from ._topography_run import zero_note

        # Each other model's K with its own status beside it: a NaN says why.
        others = {name: (np.where(s.ok, s.stiffness, np.nan), np.asarray(s.status)) for name, s in others.items()}
        for k, (row, lower, upper) in enumerate(zip(rows, band.lower, band.upper)):
            row["K_lower_95_N_per_m"], row["K_upper_95_N_per_m"] = float(lower), float(upper)
            for name, (K, status) in others.items():
                row[f"K_{name}_N_per_m"], row[f"status_{name}"] = float(K[k]), status_message(status[k])
        notes[1:1] = [n for n in [zero_note(spec.scene.model.name, solution)] if n]
    if spec.approach_reference is not None:  # only scenes that ask for the approach compute it
        for row, extra in zip(rows, _approach_rows(spec)):
            row["approach_m"] = extra["approach_m"]
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    record = scene_record(spec)
    write_csv(rows, out / "results.csv", comments=record_comments(record))
    from ._plots import plot_sweep

    files = [str(out / "results.csv")] + plot_sweep(solution, spec.title, out)
    if band is not None:
        from ._surface_plots import plot_band

        curves = {name: K for name, (K, _) in others.items()}
        files.append(plot_band(band, spec.title, out / "stiffness_band.png", curves, spec.scene.model.name))
    choices = ", ".join(f"{k} {v!r}" for k, v in spec.scene.model.options().items())
    flagged = flagged_summary(solution.status)
    plastic = int(np.sum(solution.fully_plastic))
    if plastic:
        flagged += f"; {plastic} fully plastic (K = 0: every contact spot is plastic, Sec. 4.2)"
    summary = (
        f"{spec.title}\n{choices}; {flagged}\n"
        + "".join(f"{n}\n" for n in notes)
        + f"\n{format_table(rows, _columns(rows))}\n\n"
        + "\n".join(f"wrote {f}" for f in files)
    )
    payload = {"title": spec.title, "source": spec.source, "scene": record, "flagged": flagged, "warnings": warnings}
    payload["notes"] = notes
    payload["rows"] = rows
    print_result({**payload, "files": files}, args.format, summary)
    return 0


# What `run` says K is when it is not the loading tangent.
STIFFNESS_WORDS = {
    "unloading": "unloading (dynamic) stiffness about each load: every spot unloads elastically from its state there",
    "tangential": "tangential stiffness in full stick (Mindlin) at each load",
}


def _columns(rows) -> tuple[str, ...]:
    """The table's columns: the usual ones, and a topography run's band and other models beside K."""
    usual = ("F_N", "F_star", "a_l_m2", "K_N_per_m", "K_star", "status")
    if not rows or "K_lower_95_N_per_m" not in rows[0]:
        return usual
    extra = [c for c in rows[0] if (c.startswith("K_") or c.startswith("status_")) and c not in usual]
    return ("F_N", "F_star", "K_N_per_m", "status", *extra)


def _approach_rows(spec):
    import numpy as np

    from ..applications import approach
    from ..quantities import status_message

    result = approach(spec.scene, spec.loads, spec.approach_reference)
    return [
        {"F_N": float(F), "F_star": float(Fs), "approach_m": float(d), "status": status_message(s)}
        for F, Fs, d, s in zip(spec.loads, spec.load_star, np.asarray(result.approach), np.asarray(result.status))
    ]


def _require(spec, effect: str, table: str) -> None:
    if getattr(spec, effect) is None:
        raise CommandError(
            f"{spec.source} does not ask for this effect: add a [{table}] table (see data/scenes/table1_dynamics.toml)"
        )


def _require_valid_preload(scene, load: float, key: str) -> None:
    """A preload where the model gives no stiffness makes every row meaningless: refuse it."""
    from ..core import solve
    from ..quantities import status_message

    status = int(solve(scene, load).status)
    if status != 0:
        raise CommandError(
            f"{key} = {load:g} N is outside the model ({status_message(status)}): choose a preload where the "
            "stiffness is valid (see jaxcontact run on this scene)"
        )


def cmd_approach(args) -> int:
    import numpy as np

    from ._report import format_table, write_csv
    from ._scenefile import DYNAMICS_SCENE, load_scene

    spec = load_scene(args.scene, default=DYNAMICS_SCENE)
    _require(spec, "approach_reference", "approach")
    _require_valid_preload(spec.scene, spec.approach_reference, "approach.reference_load")
    rows = _approach_rows(spec)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "approach.csv")
    from ._plots import plot_approach

    files = [
        str(out / "approach.csv"),
        plot_approach(
            spec.load_star, np.array([r["approach_m"] for r in rows]), spec.approach_reference, out / "approach.png"
        ),
    ]
    text = (
        f"{spec.title}: approach relative to F0 = {spec.approach_reference:g} N\n\n"
        + format_table(rows, ("F_N", "F_star", "approach_m", "status"))
        + "\n\n"
        + "\n".join(f"wrote {f}" for f in files)
    )
    print_result(
        {"title": spec.title, "reference_load_N": spec.approach_reference, "rows": rows, "files": files},
        args.format,
        text,
    )
    return 0


def add_dynamics_options(p) -> None:
    p.add_argument(
        "--stiffness",
        choices=("unloading", "loading"),
        default="unloading",
        help="the joint's law about the preload: unloading (default: the dynamic stiffness of a joint "
        "pressed once, docs/in-service.md) or loading (the reversible loading law)",
    )


def cmd_dynamics(args) -> int:
    import numpy as np

    from ..applications import Drive, frequency_response, map_in_chunks, resonance_frequency, simulate
    from ..core._settings import STIFFNESSES
    from ..quantities import status_message
    from ._report import write_csv
    from ._scenefile import DYNAMICS_SCENE, load_scene

    spec = load_scene(args.scene, default=DYNAMICS_SCENE)
    _require(spec, "dynamics", "dynamics")
    d = spec.dynamics
    law = STIFFNESSES[args.stiffness]()
    f_linear, status = resonance_frequency(spec.scene, d.mass, np.array([d.preload]), stiffness=law)
    f_linear, status = float(f_linear[0]), int(status[0])
    if status != 0:
        raise CommandError(
            f"the joint has no valid stiffness at the preload {d.preload:g} N ({status_message(status)})"
        )
    if not f_linear > 0:
        raise CommandError(
            f"the joint's {law.name} stiffness at the preload {d.preload:g} N is 0 (every spot flows): "
            "its dynamic stiffness is --stiffness unloading"
        )
    damping = d.damping if d.damping is not None else 2 * d.damping_ratio * d.mass * 2 * np.pi * f_linear
    drive = Drive(
        mass=d.mass, damping=damping, preload=d.preload, amplitude=d.amplitude, frequency=d.frequency or f_linear
    )
    history = simulate(spec.scene, drive, stiffness=law, periods=20)
    sweep_hz = np.linspace(*d.sweep, d.sweep_count) * f_linear
    amplitudes, statuses = map_in_chunks(
        lambda f: frequency_response(spec.scene, drive, f, stiffness=law),
        sweep_hz,
        chunk=8,
        progress=args.progress,
        desc="frequency sweep",
    )
    peak = int(np.nanargmax(amplitudes))
    f_res, res_status = (np.asarray(x) for x in resonance_frequency(spec.scene, d.mass, spec.loads, stiffness=law))
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(
        [
            {"t_s": float(t), "x_m": float(x), "v_m_per_s": float(v), "contact_force_N": float(F)}
            for t, x, v, F in zip(history.t, history.x, history.v, history.contact_force)
        ],
        out / "time_history.csv",
    )
    sweep_rows = [
        {"frequency_Hz": float(f), "amplitude_m": float(a), "status": status_message(s)}
        for f, a, s in zip(sweep_hz, amplitudes, statuses)
    ]
    write_csv(sweep_rows, out / "frequency_response.csv")
    resonance_rows = [
        {"preload_N": float(F), "resonance_Hz": float(f), "status": status_message(s)}
        for F, f, s in zip(spec.loads, f_res, res_status)
    ]
    write_csv(resonance_rows, out / "resonance_vs_preload.csv")
    files = [str(out / n) for n in ("time_history.csv", "frequency_response.csv", "resonance_vs_preload.csv")]
    from ._plots import plot_dynamics

    files += plot_dynamics(history, sweep_hz, amplitudes, f_linear, spec.loads, f_res, out)
    summary = {
        "title": spec.title,
        "mass_kg": d.mass,
        "preload_N": d.preload,
        "amplitude_N": d.amplitude,
        "damping_N_s_per_m": damping,
        "stiffness": law.name,
        "linear_resonance_Hz": f_linear,
        "sweep_peak_Hz": float(sweep_hz[peak]),
        "peak_amplitude_m": float(amplitudes[peak]),
        "frequency_response": sweep_rows,
        "resonance_vs_preload": resonance_rows,
        "files": files,
    }
    text = (
        f"{spec.title}\nmass {d.mass:g} kg, preload {d.preload:g} N, drive {d.amplitude:g} N, "
        f"damping {damping:.4g} N s/m\nthe joint's {law.name} law: linear resonance sqrt(K(F0)/m)/2π = "
        f"{f_linear:.6g} Hz; "
        f"sweep peak at {sweep_hz[peak]:.6g} Hz, amplitude {amplitudes[peak]:.4g} m\n"
        + "\n".join(f"wrote {f}" for f in files)
    )
    print_result(summary, args.format, text)
    return 0
