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
    import jax

    jax.config.update("jax_enable_x64", True)
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
    import numpy as np

    from .bench import baseline_ratio, effects_table
    from .scenefile import load_scene

    spec = load_scene(args.scene)
    E, A = float(spec.scene.material.E), float(spec.scene.area)
    curve = np.geomspace(1e-7, 1e-4, 200) * E * A
    sweep = np.geomspace(1e-7, 1e-4, 20_000) * E * A
    effects = effects_table(spec.scene, sweep)
    ratio = baseline_ratio(spec.scene, curve)
    base = effects[0]["run_s"]
    lines = [f"{spec.title}: what each effect costs, 20000 loads, F* 1e-7 … 1e-4, after compilation (best of 5)", "",
             f"{'variant':40s} {'compile (s)':>11s} {'run (ms)':>9s} {'vs leanest':>10s} {'points/s':>10s}"]
    for r in effects:
        lines.append(f"{r['variant']:40s} {r['compile_s']:11.2f} {1e3 * r['run_s']:9.3f} "
                     f"{r['run_s'] / base:9.2f}x {r['points_per_s']:10.3g}")
    lines += ["", f"scipy baseline (quad + brentq), {ratio['points']} loads: {ratio['scipy_s']:.2f} s; "
              f"jaxcontact {1e3 * ratio['jaxcontact_s']:.2f} ms: {ratio['speedup']:.0f}x faster"]
    _print({"scene": spec.title, "effects": effects, "baseline": ratio}, args.format, "\n".join(lines))
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


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="jaxcontact", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)

    def common(p, default_out):
        p.add_argument("--format", choices=("table", "json"), default="table", help="output format on stdout")
        p.add_argument("--out", default=default_out, help=f"output folder (default: {default_out})")
        p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")

    p = sub.add_parser("run", help="solve a scene (default: the embedded Table 1 scene), write CSV and plots")
    p.add_argument("scene", nargs="?", help="scene TOML file (default: embedded table1_grinding.toml)")
    common(p, "jaxcontact-out")
    p.set_defaults(func=cmd_run)

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

    p = sub.add_parser("bench", help="time the compiled model: each effect's cost, speed against scipy")
    p.add_argument("scene", nargs="?", help="scene TOML file (default: embedded)")
    common(p, "jaxcontact-out")
    p.set_defaults(func=cmd_bench)
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
