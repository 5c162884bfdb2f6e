"""`jaxcontact compare`: every model beside the elastic boundary-element reference (MODEL.md §9–10)."""

from __future__ import annotations

import math
import pathlib

from .commands import CommandError, print_result

DEFAULT_COMPARE_SCENE = "bem_comparison.toml"


def add_compare_options(p) -> None:
    p.add_argument(
        "--grid",
        type=int,
        default=512,
        help="BEM grid, points per side, a power of two (default 512); a finer measured map is coarsened to it",
    )
    p.add_argument("--realisations", type=int, default=3, help="synthesised surfaces per scene (default 3)")
    p.add_argument("--seed", type=int, default=0, help="seed of the first realisation (default 0)")
    p.add_argument(
        "--cache-dir", help="where BEM results are kept (default: $JAXCONTACT_CACHE_DIR or ~/.cache/jaxcontact)"
    )
    p.add_argument("--no-cache", action="store_true", help="solve every load again, keep nothing")
    p.add_argument("--validation", action="store_true", help="the validation table: D = 1.3, 1.5, 1.7 on the scene")
    p.add_argument("--substrate", choices=("periodic", "free"), help="half-space for a measured map (--topography)")
    p.add_argument(
        "--no-fit", dest="fit", action="store_false", help="with --topography: skip the fits to the BEM curve"
    )


def _progress(args, total_label: str):
    if not args.progress:
        return None
    from tqdm.auto import tqdm

    bar = {}

    def update(done, total):
        if "bar" not in bar:
            bar["bar"] = tqdm(total=total, desc=total_label, unit="load")
        bar["bar"].update(done - bar["bar"].n)
        if done == total:
            bar["bar"].close()

    return update


def _cache(args):
    from ..bem import ResultCache

    return None if args.no_cache else ResultCache(args.cache_dir)


def _scene(args):
    from .scenefile import load_scene

    if args.scene is None:
        import importlib.resources

        path = importlib.resources.files("jaxcontact").joinpath("scenes", DEFAULT_COMPARE_SCENE)
        return load_scene(str(path))
    return load_scene(args.scene)


def _ratio_cell(row, label) -> str:
    from ..studies.compare import column_key

    key = column_key(label)
    status = row[f"status_{key}"]
    return f"{row['ratio_' + key]:>15.3g}" if status == "ok" else f"{status[:15]:>15}"


def _table(rows, labels) -> str:
    head = f"{'F*':>10} {'A_r/A_a':>8} {'K*_BEM':>10} " + " ".join(f"{label:>15}" for label in labels)
    lines = [head]
    for row in rows:
        cells = " ".join(_ratio_cell(row, label) for label in labels)
        lines.append(f"{row['F_star']:>10.3g} {row['contact_fraction_bem']:>8.3%} {row['K_star_bem']:>10.4g} {cells}")
    return "\n".join(lines)


def plot_comparison(comparison, title, path) -> str:
    import numpy as np

    from .plots import save_figure, subplots

    ref = comparison.reference
    unit_load = float(comparison.scene.material.E) * float(comparison.scene.area)
    unit_stiffness = float(comparison.scene.material.E) * math.sqrt(float(comparison.scene.area))
    from matplotlib.ticker import NullFormatter

    from ..studies.compare import model_curves

    F = ref.loads / unit_load
    # 32 loads: the load-array bucket of the table's own loads, so the plot compiles nothing new.
    fine = np.geomspace(ref.loads.min(), ref.loads.max(), 32)
    fig, ax = subplots(figsize=(6.5, 4.6))
    for label, (stiffness, _) in model_curves(comparison.scene, fine).items():
        shown = np.isfinite(stiffness) & (stiffness > 0)
        note = "" if shown.all() else (" (flagged or K = 0 everywhere)" if not shown.any() else " (partly flagged)")
        ax.loglog(fine[shown] / unit_load, stiffness[shown] / unit_stiffness, "-", label=label + note)
    mean = ref.mean / unit_stiffness
    ax.errorbar(
        F,
        mean,
        yerr=[mean - ref.low / unit_stiffness, ref.high / unit_stiffness - mean],
        fmt="ko",
        capsize=3,
        label=f"BEM {ref.grid}², {len(ref.seeds)} realisations (min–max)",
    )
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("F* = F/(E A_a)")
    ax.set_ylabel("K* = K/(E √A_a)")
    ax.set_title(title, fontsize=8)
    ax.legend(fontsize=7)
    return save_figure(fig, path)


def cmd_compare(args) -> int:
    from ..numerics.validate import optional_import
    from ..studies.compare import COMPARED, compare_scene, validation_rows
    from .report import write_csv

    optional_import("ContactMechanics", "the boundary-element reference of jaxcontact compare")  # before any work

    out = pathlib.Path(args.out)
    if args.topography:
        from .compare_measured import compare_measured

        return compare_measured(args, out, _cache(args), _progress(args, "BEM"))
    spec = _scene(args)
    options = dict(grid=args.grid, realisations=args.realisations, seed=args.seed, cache=_cache(args))
    labels = list(COMPARED)
    if args.validation:
        rows = validation_rows(spec.scene, progress=_progress(args, "BEM"), convergence=False, **options)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(
            rows,
            out / "validation.csv",
            comments=[
                f"jaxcontact compare --validation --grid {args.grid} "
                f"--realisations {args.realisations} --seed {args.seed}"
            ],
        )
        text = "\n\n".join(
            f"D = {D}\n" + _table([r for r in rows if r["D"] == D], labels) for D in sorted({r["D"] for r in rows})
        )
        files = [str(out / "validation.csv")]
        print_result({"rows": rows, "files": files}, args.format, f"{text}\n\nwrote {files[0]}")
        return 0
    comparison = compare_scene(spec.scene, spec.loads, progress=_progress(args, "BEM"), **options)
    if not comparison.reference.ok.any():
        raise CommandError("the BEM gave no valid point at these loads (see the status column of comparison.csv)")
    rows = comparison.rows()
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "comparison.csv")
    files = [str(out / "comparison.csv"), plot_comparison(comparison, spec.title, out / "comparison.png")]
    change = comparison.reference.grid_change
    convergence = (
        ""
        if change is None
        else (
            f"grid convergence: K at {args.grid // 2}² differs from {args.grid}² by at most "
            f"{float(abs(change[comparison.reference.ok]).max()):.2%}\n"
        )
    )
    summary = (
        f"{spec.title}\nK_model / K_BEM (BEM: {args.grid}², mean of {args.realisations} realisations)\n"
        f"{_table(rows, labels)}\n{convergence}\n" + "\n".join(f"wrote {f}" for f in files)
    )
    print_result({"title": spec.title, "rows": rows, "files": files}, args.format, summary)
    return 0
