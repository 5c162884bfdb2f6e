"""`jaxcontact cycle`: the joint's friction loops about a preload (`jc.tangential_cycle`) and its normal
load path (`jc.solve_path`), as CSV and plots."""

from __future__ import annotations

import pathlib

from ._output import CommandError, add_log_range, print_result

# Default amplitudes: from 1e-3 to 1e2 times μF/k_t, full stick to macroslip.
DEFAULT_SPAN = (1e-3, 1e2)
LOOPS = (0.3, 1.0, 3.0, 10.0)  # the loops drawn, in units of μF/k_t
LOOP_POINTS = 40
COLUMNS = ("u0_m", "Q0_N", "W_J", "secant_N_per_m", "damping_ratio", "sliding_share", "status")


def cmd_cycle(args) -> int:
    import jax.numpy as jnp
    import numpy as np

    from ..core import tangential_cycle, tangential_stiffness
    from ..quantities import status_message
    from ._report import format_table, record_comments, scene_record, write_csv
    from ._scenefile import load_scene

    spec = load_scene(args.scene)
    scene, friction = spec.scene, spec.friction
    mu = args.mu if args.mu is not None else None if friction is None else friction.mu
    loads = args.path or spec.path
    if mu is None and loads is None:
        raise CommandError(
            "nothing to cycle: give --mu MU ([friction] mu) for friction loops, or --path F1 F2 ... ([path] loads) "
            "for a normal load path"
        )
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if loads is not None:
        if len(loads) < 2 or not all(0 < F < float("inf") for F in loads):
            raise CommandError(f"--path {' '.join(f'{F:g}' for F in loads)} must be at least two loads (N) > 0")
        from ._path_command import COLUMNS as PATH_COLUMNS
        from ._path_command import run_path

        path_rows, path_files, path_text = run_path(spec, loads, out)
        path_text = f"{spec.title}: {path_text}\n\n" + format_table(path_rows, PATH_COLUMNS)
        if mu is None:
            text = path_text + "".join(f"\nwrote {f}" for f in path_files)
            payload = {"title": spec.title, "path": path_rows, "files": path_files}
            print_result(payload, args.format, text)
            return 0
    if not 0 < mu < float("inf"):
        raise CommandError(f"--mu {mu:g} must be a friction coefficient > 0")
    preload = args.preload or (friction.preload if friction and friction.preload else _middle(spec.loads))
    if not 0 < preload < float("inf"):
        raise CommandError(f"--preload {preload:g} must be a load (N) > 0")
    if args.points < 2:
        raise CommandError(f"--points {args.points} must be at least 2")
    stick = float(tangential_stiffness(scene, preload).stiffness)
    if not np.isfinite(stick) or stick <= 0:
        raise CommandError(f"the model has no tangential stiffness at the preload {preload:g} N: choose another")
    scale = mu * preload / stick  # the displacement at which a linear spring reaches μF
    given = args.amplitudes or (friction.amplitudes if friction and friction.amplitudes else None)
    low, high = given or (DEFAULT_SPAN[0] * scale, DEFAULT_SPAN[1] * scale)
    if not 0 < low < high < float("inf"):
        raise CommandError(f"--amplitudes {low:g} {high:g} must be two displacements (m) with 0 < low < high")
    amplitudes = np.geomspace(low, high, args.points)
    # The loops' branches are the backbone at (u₀ ± u)/2: one call with the table's amplitudes.
    # Geometric near the tip (s → 0), where B rises at k_t and the branch turns fastest; even beyond.
    fractions = np.union1d(np.geomspace(1e-4, 1.0, LOOP_POINTS // 2), np.linspace(0.0, 1.0, LOOP_POINTS // 2 + 1)[1:])
    halves = np.concatenate([u0 * fractions for u0 in scale * np.asarray(LOOPS)])
    cycle = tangential_cycle(scene, preload, jnp.asarray(np.concatenate([amplitudes, halves])), mu)
    columns = [np.asarray(getattr(cycle, name)) for name in _FIELDS]
    n = len(amplitudes)
    rows = [
        dict(zip(COLUMNS[:-1], (float(x[i]) for x in columns[:-1]))) | {"status": status_message(int(columns[-1][i]))}
        for i in range(n)
    ]
    csv = str(out / "cycle.csv")
    provenance = record_comments(scene_record(spec)) + [f"preload = {preload:.10g} N, mu = {mu:.10g}"]
    write_csv(rows, csv, comments=provenance)
    from ._plots import plot_cycle

    backbone = columns[1][n:].reshape(len(LOOPS), fractions.size)
    figure = plot_cycle(
        amplitudes,
        columns[1][:n],
        columns[4][:n],
        fractions,
        backbone,
        mu * preload,
        out / "cycle.png",
        scale * np.asarray(LOOPS),
    )
    text = (
        f"{spec.title}: friction loops about F = {preload:g} N, mu = {mu:g} (Cattaneo–Mindlin spots, Masing's rules)\n"
        f"stick stiffness k_t = {float(cycle.stick_stiffness):.4g} N/m, macroslip force mu F = {mu * preload:.4g} N, "
        f"mu F / k_t = {scale:.3g} m\n\n"
        + format_table(rows[:: max(1, n // 12)], COLUMNS)
        + f"\n\nwrote {csv} (every amplitude)\nwrote {figure}"
    )
    payload = {
        "title": spec.title,
        "preload_N": preload,
        "mu": mu,
        "stick_stiffness_N_per_m": float(cycle.stick_stiffness),
        "macroslip_force_N": mu * preload,
    }
    files = [csv, figure]
    if loads is not None:
        text = path_text + "".join(f"\nwrote {f}" for f in path_files) + "\n\n" + text
        payload, files = payload | {"path": path_rows}, path_files + files
    print_result(payload | {"rows": rows, "files": files}, args.format, text)
    return 0


_FIELDS = ("amplitude", "force", "dissipation", "secant_stiffness", "damping_ratio", "sliding_share", "status")


def _middle(loads) -> float:
    """The scene's middle load on a log scale: the default preload."""
    import numpy as np

    return float(np.exp(np.median(np.log(np.asarray(loads)))))


def add_cycle_options(p) -> None:
    from ._path_command import add_path_option

    p.add_argument("--mu", type=float, help="friction coefficient (default: the scene's [friction] mu)")
    add_path_option(p)
    p.add_argument(
        "--preload", type=float, help="normal load F (N) (default: [friction] preload, or the scene's middle load)"
    )
    add_log_range(p, "amplitudes", "tangential displacement amplitudes (m)", "1e-3 to 1e2 times mu F / k_t", 60)
