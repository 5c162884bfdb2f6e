"""The commands that study the library or sweep it: figures, bench, accuracy, sweep."""

from __future__ import annotations

import pathlib
import sys

from ._output import CommandError, print_result, progress_bar


def add_bench_options(p) -> None:
    p.add_argument(
        "--bem",
        action="store_true",
        help="time the JAX boundary-element solve against ContactMechanics instead (minutes; the JAX solve "
        "alone where ContactMechanics is not installed)",
    )
    p.add_argument(
        "--bem-grids",
        type=int,
        nargs="+",
        default=[256, 512, 1024],
        metavar="N",
        help="with --bem: the grids timed (default 256 512 1024)",
    )
    p.add_argument(
        "--fit-batch",
        type=int,
        metavar="CURVES",
        help="time fitting.fit_batch on this many 30-point curves against looping fitting.fit instead (minutes)",
    )


def cmd_figures(args) -> int:
    from ..studies._figures import make_figures

    progress = progress_bar(args.progress, "figures", "figure")
    files = make_figures(args.out, progress=progress)
    print_result({"files": files}, args.format, "\n".join(f"wrote {f}" for f in files))
    return 0


def cmd_bench(args) -> int:
    import datetime
    import os
    import platform

    if args.bem:
        return _bench_bem(args)
    if args.fit_batch is not None:
        return _bench_fit_batch(args)
    from ..studies._bench import run_all
    from ..studies._bench_report import format_markdown, format_results
    from ._exported import exported_programs
    from ._report import scene_record, to_json
    from ._scenefile import load_scene

    spec = load_scene(args.scene)
    progress = progress_bar(args.progress, "benchmarks", "step")
    # Timed as a user's process calls the model: traced, not read from the command line's store.
    with exported_programs(None):
        results = run_all(spec.scene, progress=progress)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    text = f"{spec.title}\n" + format_results(results)
    payload = {"scene": scene_record(spec), **results}
    (out / "bench.txt").write_text(text + "\n")
    (out / "bench.json").write_text(to_json(payload) + "\n")
    machine = (
        f"{platform.machine()} {platform.processor() or 'CPU'}, {os.cpu_count()} cores ({results.get('device', 'cpu')})"
    )
    (out / "bench.md").write_text(format_markdown(results, machine, datetime.date.today().isoformat()) + "\n")
    files = [str(out / name) for name in ("bench.txt", "bench.json", "bench.md")]
    print_result({**payload, "files": files}, args.format, text + "\n\n" + "\n".join(f"wrote {f}" for f in files))
    return 0


def _bench_bem(args) -> int:
    from ..bem._surfaces import check_grid_points
    from ..numerics import MissingExtraError, optional_import
    from ..studies._bem_bench import format_bem_bench, run_bem_bench

    for grid in args.bem_grids:
        check_grid_points(grid)
    try:
        optional_import("ContactMechanics", "jaxcontact bench --bem's comparison")
        reference = True
    except MissingExtraError as missing:
        print(f"{missing}: the JAX solve is timed alone", file=sys.stderr)
        reference = False
    progress = progress_bar(args.progress, "boundary-element benchmarks", "step")
    results = run_bem_bench(tuple(args.bem_grids), reference=reference, progress=progress)
    return _written(args, "bench_bem", results, format_bem_bench(results))


def _written(args, name: str, results: dict, text: str) -> int:
    """`NAME.txt` (the text) and `NAME.json` (the results) in `args.out`, and the output printed."""
    from ._report import to_json

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{name}.txt").write_text(text + "\n")
    (out / f"{name}.json").write_text(to_json(results) + "\n")
    files = [str(out / f"{name}.txt"), str(out / f"{name}.json")]
    print_result({**results, "files": files}, args.format, text + "\n\n" + "\n".join(f"wrote {f}" for f in files))
    return 0


def _bench_fit_batch(args) -> int:
    from ..studies._fit_bench import format_fit_bench, run_fit_bench
    from ._scenefile import load_scene

    if args.fit_batch < 1:
        raise CommandError(f"--fit-batch {args.fit_batch} must be a number of curves >= 1")
    results = run_fit_bench(load_scene(args.scene).scene, curves=args.fit_batch)
    return _written(args, "bench_fit_batch", results, format_fit_bench(results))


def cmd_accuracy(args) -> int:
    from ._scenefile import load_scene

    try:
        from ..studies._accuracy import format_study, plot_study, study
    except ModuleNotFoundError as exc:
        if exc.name != "mpmath":
            raise
        raise CommandError(
            "the accuracy study needs mpmath for its reference: pip install 'jaxcontact[studies]'"
        ) from None

    spec = load_scene(args.scene)
    options = spec.scene.model.options()
    if options["model"] != "xia2024" or options["distribution"] != "mb":
        raise CommandError("the accuracy study needs a scene with model 'xia2024' and distribution 'mb'")
    progress = progress_bar(args.progress, "knobs", "knob")
    result = study(spec.scene, progress=progress)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [plot_study(result, out / "accuracy.png")]
    print_result(
        {**result, "files": files}, args.format, format_study(result) + "\n\n" + "\n".join(f"wrote {f}" for f in files)
    )
    return 0


def _grid(text: str, name: str, log: bool):
    import numpy as np

    try:
        low, high, count = text.split(":")
        low, high, count = float(low), float(high), int(count)
    except ValueError:
        raise CommandError(
            f"--{name} {text!r} must be LOW:HIGH:COUNT, e.g. " + ("1e-11:1e-9:5" if log else "1.3:1.7:5")
        ) from None
    if count < 1 or high < low or (log and low <= 0):
        raise CommandError(f"--{name} {text!r}: need COUNT >= 1 and LOW <= HIGH" + (" with LOW > 0" if log else ""))
    return np.geomspace(low, high, count) if log else np.linspace(low, high, count)


# What one point of a sweep holds until its CSV is written: its row (a dict of eight values) and its
# share of the result arrays.
BYTES_PER_POINT = 1024


def _check_memory(points: int, what: str) -> None:
    """Refuse, before computing, a sweep whose rows would not fit in the memory free now."""
    import os

    free = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")
    need = points * BYTES_PER_POINT
    if need > free:
        raise CommandError(
            f"{what} = {points:.3g} points would need about {need / 2**30:.3g} GiB, and {free / 2**30:.3g} GiB "
            "is free: sweep a coarser grid, or the grid in parts"
        )


def cmd_sweep(args) -> int:
    import jax

    from ..applications import sweep
    from ..quantities import Scales, status_message
    from ._report import write_csv
    from ._scenefile import load_scene

    if args.distributed:
        jax.distributed.initialize()
    spec = load_scene(args.scene)
    D, G = _grid(args.D, "D", log=False), _grid(args.G, "G", log=True)
    _check_memory(D.size * G.size * spec.loads.size, f"--D {args.D} × --G {args.G} × {spec.loads.size} loads")
    result = sweep(spec.scene, D, G, spec.loads, progress=args.progress)
    scales = Scales.of(spec.scene)
    load_unit, stiffness_unit = float(scales.load), float(scales.stiffness)
    rows = [
        {
            "D": float(d),
            "G_m": float(g),
            "F_N": float(F),
            "F_star": float(F) / load_unit,
            "a_l_m2": float(result.a_l[i, j, k]),
            "K_N_per_m": float(result.stiffness[i, j, k]),
            "K_star": float(result.stiffness[i, j, k]) / stiffness_unit,
            "status": status_message(result.status[i, j, k]),
        }
        for i, d in enumerate(D)
        for j, g in enumerate(G)
        for k, F in enumerate(result.loads)
    ]
    files = []
    if jax.process_index() == 0:
        out = pathlib.Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(rows, out / "sweep.csv")
        files.append(str(out / "sweep.csv"))
    flagged = sum(r["status"] != "ok" for r in rows)
    text = (
        f"{spec.title}: {D.size} D × {G.size} G × {result.loads.size} loads = {len(rows)} points on "
        f"{result.devices} device(s), {flagged} flagged\n" + "\n".join(f"wrote {f}" for f in files)
    )
    print_result(
        {
            "title": spec.title,
            "devices": result.devices,
            "points": len(rows),
            "flagged": flagged,
            "files": files,
            "rows": rows if args.format == "json" else [],
        },
        args.format,
        text,
    )
    return 0
