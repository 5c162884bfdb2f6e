"""The `jaxcontact` command line: run a scene, draw the paper's figures, time the model.

Runs in float64 and keeps a persistent compilation cache, so repeated runs skip compilation.
User mistakes (bad scene files, bad options) end with exit status 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys

EXIT_USAGE = 2


class CommandError(Exception):
    """A user mistake to report in one line."""


def _setup_jax():
    import gc

    import jax

    from . import solve  # noqa: F401  (the package and its dependencies, imported before the freeze)

    jax.config.update("jax_enable_x64", True)
    # Run each compiled call on the calling thread. Handing it to a worker thread (JAX's default
    # on CPU) costs more than it hides when a call takes ~0.1 ms, and its pool's spinning threads
    # compete for 2 cores (openxla/xla#18608): a 200-load curve took 100-113 µs instead of
    # 115-150 (best of 2000 calls; the median 138-163 µs instead of 194-281), and 1e5 loads were
    # no slower. Sharded (multi-device) computations stay asynchronous.
    jax.config.update("jax_cpu_enable_async_dispatch", False)
    # JAXCONTACT_CACHE="" turns the persistent compilation cache off.
    cache = os.environ.get("JAXCONTACT_CACHE", str(pathlib.Path.home() / ".cache" / "jaxcontact" / "xla"))
    if cache:
        try:
            pathlib.Path(cache).mkdir(parents=True, exist_ok=True)
            jax.config.update("jax_compilation_cache_dir", cache)
            jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
            jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
        except OSError:
            pass  # a read-only home: run without the cache
    # The modules just imported live as long as the process: leave them out of every garbage
    # collection. Tracing a model allocates millions of short-lived objects, and each full
    # collection it triggers would otherwise walk the whole of jax, numpy and scipy again
    # (tracing the "paper" solve: 0.33-0.50 s frozen against 0.62-0.63 s).
    gc.freeze()


def _print(payload, fmt: str, text: str) -> None:
    from .report import to_json

    print(to_json(payload) if fmt == "json" else text)


def cmd_run(args) -> int:
    from .plots import plot_sweep
    from .report import format_table, solution_rows, write_csv
    from .runner import solve_sweep
    from .scenefile import load_scene

    spec = load_scene(args.scene)
    solution = solve_sweep(spec.scene, spec.loads, progress=args.progress and spec.loads.size > 4096)
    rows = solution_rows(solution)
    if spec.approach_reference is not None:  # only scenes that ask for the approach compute it
        for row, extra in zip(rows, _approach_rows(spec)):
            row["approach_m"] = extra["approach_m"]
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "results.csv")
    files = [str(out / "results.csv")] + plot_sweep(solution, spec.title, out)
    flagged = sum(r["status"] != "ok" for r in rows)
    summary = (f"{spec.title}\n{spec.scene.model}, interaction {spec.scene.interaction!r}, distribution "
               f"{spec.scene.distribution!r}; {len(rows)} loads, {flagged} flagged\n\n{format_table(rows)}\n\n"
               + "\n".join(f"wrote {f}" for f in files))
    _print({"title": spec.title, "source": spec.source, "rows": rows, "files": files}, args.format, summary)
    return 0


def _approach_rows(spec):
    import numpy as np

    from .approach import approach
    from .status import status_message

    result = approach(spec.scene, spec.loads, spec.approach_reference)
    return [{"F_N": float(F), "F_star": float(Fs), "approach_m": float(d), "status": status_message(s)}
            for F, Fs, d, s in zip(spec.loads, spec.load_star, np.asarray(result.approach), np.asarray(result.status))]


def _require(spec, effect: str, table: str) -> None:
    if getattr(spec, effect) is None:
        raise CommandError(f"{spec.source} does not ask for this effect: add a [{table}] table "
                           f"(see data/scenes/table1_dynamics.toml)")


def cmd_approach(args) -> int:
    import numpy as np

    from .plots import plot_approach
    from .report import format_table, write_csv
    from .scenefile import DYNAMICS_SCENE, load_scene

    spec = load_scene(args.scene, default=DYNAMICS_SCENE)
    _require(spec, "approach_reference", "approach")
    rows = _approach_rows(spec)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "approach.csv")
    files = [str(out / "approach.csv"), plot_approach(spec.load_star, np.array([r["approach_m"] for r in rows]),
                                                      spec.approach_reference, out / "approach.png")]
    text = (f"{spec.title}: approach relative to F0 = {spec.approach_reference:g} N\n\n"
            + format_table(rows, ("F_N", "F_star", "approach_m", "status")) + "\n\n"
            + "\n".join(f"wrote {f}" for f in files))
    _print({"title": spec.title, "reference_load_N": spec.approach_reference, "rows": rows, "files": files},
           args.format, text)
    return 0


def cmd_dynamics(args) -> int:
    import numpy as np

    from .dynamics import Drive, frequency_response, resonance_frequency, simulate
    from .plots import plot_dynamics
    from .report import write_csv
    from .runner import map_in_chunks
    from .scenefile import DYNAMICS_SCENE, load_scene
    from .status import status_message

    spec = load_scene(args.scene, default=DYNAMICS_SCENE)
    _require(spec, "dynamics", "dynamics")
    d = spec.dynamics
    f_linear, status = resonance_frequency(spec.scene, d.mass, np.array([d.preload]))
    f_linear, status = float(f_linear[0]), int(status[0])
    if status != 0:
        raise CommandError(f"the joint has no valid stiffness at the preload {d.preload:g} N ({status_message(status)})")
    damping = d.damping if d.damping is not None else 2 * d.damping_ratio * d.mass * 2 * np.pi * f_linear
    drive = Drive(mass=d.mass, damping=damping, preload=d.preload, amplitude=d.amplitude,
                  frequency=d.frequency or f_linear)
    history = simulate(spec.scene, drive, periods=20)
    sweep_hz = np.linspace(*d.sweep, d.sweep_count) * f_linear
    amplitudes, statuses = map_in_chunks(lambda f: frequency_response(spec.scene, drive, f), sweep_hz, chunk=8,
                                         progress=args.progress, desc="frequency sweep")
    peak = int(np.nanargmax(amplitudes))
    f_res, res_status = (np.asarray(x) for x in resonance_frequency(spec.scene, d.mass, spec.loads))
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv([{"t_s": float(t), "x_m": float(x), "v_m_per_s": float(v), "contact_force_N": float(F)}
               for t, x, v, F in zip(history.t, history.x, history.v, history.contact_force)], out / "time_history.csv")
    sweep_rows = [{"frequency_Hz": float(f), "amplitude_m": float(a), "status": status_message(s)}
                  for f, a, s in zip(sweep_hz, amplitudes, statuses)]
    write_csv(sweep_rows, out / "frequency_response.csv")
    resonance_rows = [{"preload_N": float(F), "resonance_Hz": float(f), "status": status_message(s)}
                      for F, f, s in zip(spec.loads, f_res, res_status)]
    write_csv(resonance_rows, out / "resonance_vs_preload.csv")
    files = [str(out / n) for n in ("time_history.csv", "frequency_response.csv", "resonance_vs_preload.csv")]
    files += plot_dynamics(history, sweep_hz, amplitudes, f_linear, spec.loads, f_res, out)
    summary = {"title": spec.title, "mass_kg": d.mass, "preload_N": d.preload, "amplitude_N": d.amplitude,
               "damping_N_s_per_m": damping, "linear_resonance_Hz": f_linear,
               "sweep_peak_Hz": float(sweep_hz[peak]), "peak_amplitude_m": float(amplitudes[peak]),
               "frequency_response": sweep_rows, "resonance_vs_preload": resonance_rows, "files": files}
    text = (f"{spec.title}\nmass {d.mass:g} kg, preload {d.preload:g} N, drive {d.amplitude:g} N, "
            f"damping {damping:.4g} N s/m\nlinear resonance sqrt(K(F0)/m)/2π = {f_linear:.6g} Hz; "
            f"sweep peak at {sweep_hz[peak]:.6g} Hz, amplitude {amplitudes[peak]:.4g} m\n"
            + "\n".join(f"wrote {f}" for f in files))
    _print(summary, args.format, text)
    return 0


def cmd_figures(args) -> int:
    from .figures import make_figures

    progress = None
    if args.progress:
        from tqdm.auto import tqdm

        progress = lambda items: tqdm(items, desc="figures", unit="figure")  # noqa: E731
    files = make_figures(args.out, progress=progress)
    _print({"files": files}, args.format, "\n".join(f"wrote {f}" for f in files))
    return 0


def cmd_bench(args) -> int:
    from .bench import format_results, run_all
    from .scenefile import load_scene

    spec = load_scene(args.scene)
    progress = None
    if args.progress:
        from tqdm.auto import tqdm

        progress = lambda steps: tqdm(steps, desc="benchmarks", unit="step")  # noqa: E731
    results = run_all(spec.scene, progress=progress)
    _print({"scene": spec.title, **results}, args.format, f"{spec.title}\n" + format_results(results))
    return 0


def cmd_fit(args) -> int:
    import numpy as np

    import fitting

    from .plots import plot_fit
    from .scenefile import load_scene

    spec = load_scene(args.scene)
    curve = fitting.load_curve(args.data, spec.scene)
    result = fitting.fit(curve.loads, curve.stiffness, spec.scene, params=args.params, method=args.method,
                         n_starts=args.starts)
    out = pathlib.Path(args.out)
    fine = np.geomspace(curve.loads.min(), curve.loads.max(), 200)
    from .runner import solve_sweep

    fitted = solve_sweep(result.scene, fine)
    files = [plot_fit(curve.loads, curve.stiffness, fine, fitted.stiffness, result.summary().splitlines()[1:3],
                      out / "fit.png")]
    text = f"{curve.source}: {curve.loads.size} points, scene {spec.title}\n{result.summary()}\n" + \
        "\n".join(f"wrote {f}" for f in files)
    _print({"data": curve.source, **result.to_dict(), "files": files}, args.format, text)
    return 0 if result.success else 1


def cmd_accuracy(args) -> int:
    from .accuracy import format_study, plot_study, study
    from .scenefile import load_scene

    spec = load_scene(args.scene)
    if spec.scene.model != "xia2024" or spec.scene.distribution != "mb":
        raise CommandError("the accuracy study needs a scene with model 'xia2024' and distribution 'mb'")
    progress = None
    if args.progress:
        from tqdm.auto import tqdm

        progress = lambda items: tqdm(items, desc="knobs", unit="knob")  # noqa: E731
    result = study(spec.scene, progress=progress)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [plot_study(result, out / "accuracy.png")]
    _print({**result, "files": files}, args.format, format_study(result) + "\n\n" + "\n".join(f"wrote {f}" for f in files))
    return 0


def _grid(text: str, name: str, log: bool):
    import numpy as np

    try:
        low, high, count = text.split(":")
        low, high, count = float(low), float(high), int(count)
    except ValueError:
        raise CommandError(f"--{name} {text!r} must be LOW:HIGH:COUNT, e.g. "
                           + ("1e-11:1e-9:5" if log else "1.3:1.7:5")) from None
    if count < 1 or high < low or (log and low <= 0):
        raise CommandError(f"--{name} {text!r}: need COUNT >= 1 and LOW <= HIGH" + (" with LOW > 0" if log else ""))
    return np.geomspace(low, high, count) if log else np.linspace(low, high, count)


def cmd_sweep(args) -> int:
    import jax

    from .report import write_csv
    from .scenefile import load_scene
    from .status import status_message
    from .sweep import sweep

    if args.distributed:
        jax.distributed.initialize()
    spec = load_scene(args.scene)
    D, G = _grid(args.D, "D", log=False), _grid(args.G, "G", log=True)
    result = sweep(spec.scene, D, G, spec.loads, progress=args.progress)
    E, area = float(spec.scene.material.E), float(spec.scene.area)
    rows = [{"D": float(d), "G_m": float(g), "F_N": float(F), "F_star": float(F) / (E * area),
             "a_l_m2": float(result.a_l[i, j, k]), "K_N_per_m": float(result.stiffness[i, j, k]),
             "K_star": float(result.stiffness[i, j, k]) / (E * area**0.5), "status": status_message(result.status[i, j, k])}
            for i, d in enumerate(D) for j, g in enumerate(G) for k, F in enumerate(result.loads)]
    files = []
    if jax.process_index() == 0:
        out = pathlib.Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(rows, out / "sweep.csv")
        files.append(str(out / "sweep.csv"))
    flagged = sum(r["status"] != "ok" for r in rows)
    text = (f"{spec.title}: {D.size} D × {G.size} G × {result.loads.size} loads = {len(rows)} points on "
            f"{result.devices} device(s), {flagged} flagged\n" + "\n".join(f"wrote {f}" for f in files))
    _print({"title": spec.title, "devices": result.devices, "points": len(rows), "flagged": flagged, "files": files,
            "rows": rows if args.format == "json" else []}, args.format, text)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="jaxcontact", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)

    def common(p, default_out):
        p.add_argument("--format", choices=("table", "json"), default="table", help="output format on stdout")
        p.add_argument("--out", default=default_out, help=f"output folder (default: {default_out})")
        p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")

    def scene_command(name, help, func, out, default_scene="table1_grinding.toml"):
        p = sub.add_parser(name, help=help)
        p.add_argument("scene", nargs="?", help=f"scene TOML file (default: embedded {default_scene})")
        common(p, out)
        p.set_defaults(func=func)
        return p

    scene_command("run", "solve a scene (default: the embedded Table 1 scene), write CSV and plots", cmd_run,
                  "jaxcontact-out")
    scene_command("approach", "load–approach curve relative to a preload (scenes with [approach])", cmd_approach,
                  "jaxcontact-out/approach", "table1_dynamics.toml")
    scene_command("dynamics", "a driven mass on the joint: time history, frequency response, resonance against "
                  "preload (scenes with [dynamics])", cmd_dynamics, "jaxcontact-out/dynamics", "table1_dynamics.toml")
    p = sub.add_parser("figures", help="reproduce the paper's Figs. 3, 4, 5, 6, 8 and the l_min dependence")
    common(p, "jaxcontact-out/figures")
    p.set_defaults(func=cmd_figures)

    p = sub.add_parser("fit", help="fit D and G (or other parameters) to a measured stiffness curve (CSV)")
    p.add_argument("data", help="CSV with columns load_N,stiffness_N_per_m (or F_star,K_star)")
    p.add_argument("--scene", help="scene TOML supplying the parameters that are not fitted (default: embedded)")
    p.add_argument("--params", default="D,G", help="comma-separated parameters to fit (default: D,G)")
    p.add_argument("--method", choices=("lbfgs", "lm"), default="lbfgs", help="optimiser (default: lbfgs)")
    p.add_argument("--starts", type=int, default=12, help="number of starts optimised together (default: 12)")
    common(p, "jaxcontact-out")
    p.set_defaults(func=cmd_fit)

    p = scene_command("sweep", "D × G × load grid, sharded across all JAX devices; CSV output", cmd_sweep,
                      "jaxcontact-out")
    p.add_argument("--D", default="1.3:1.7:5", help="fractal dimensions LOW:HIGH:COUNT, linear (default 1.3:1.7:5)")
    p.add_argument("--G", default="1e-11:1e-9:5", help="roughness (m) LOW:HIGH:COUNT, log-spaced (default 1e-11:1e-9:5)")
    p.add_argument("--distributed", action="store_true", help="call jax.distributed.initialize() (multi-host runs)")
    scene_command("accuracy", "error against time for every accuracy knob (reference: mpmath)", cmd_accuracy,
                  "jaxcontact-out")
    scene_command("bench", "time the compiled model: speed against scipy, each effect's cost", cmd_bench,
                  "jaxcontact-out")
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    _setup_jax()
    try:
        return args.func(args)
    except (ValueError, CommandError, OSError) as exc:  # SceneFileError and DataError are ValueErrors
        print(f"jaxcontact {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("jaxcontact: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
