"""What `jaxcontact compare` and `compare --topography` share: options, the scene, the BEM cache
and progress, the K_model/K_BEM table and the comparison plot."""

from __future__ import annotations

import math

DEFAULT_COMPARE_SCENE = "bem_comparison.toml"


def add_compare_options(p) -> None:
    p.add_argument(
        "--grid",
        type=int,
        default=512,
        help="BEM grid, points per side, a power of two (default 512); a finer measured map is coarsened to it",
    )
    p.add_argument("--realisations", type=int, default=3, help="synthesised surfaces per scene (default 3)")
    p.add_argument(
        "--reference",
        choices=("jax", "contactmechanics"),
        default="jax",
        help="boundary-element solver (default: jax; contactmechanics, the independent one, is slower)",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of the first realisation (default 0)")
    p.add_argument(
        "--cache-dir", help="where BEM results are kept (default: $JAXCONTACT_CACHE_DIR or ~/.cache/jaxcontact)"
    )
    p.add_argument("--no-cache", action="store_true", help="solve every load again, keep nothing")
    p.add_argument("--validation", action="store_true", help="the validation table: D = 1.3, 1.5, 1.7 on the scene")
    p.add_argument(
        "--scale",
        action="store_true",
        help="K against l_min = L/16 ... L/128 at one load per D = 1.3, 1.5, 1.7 (BEM grids 64² to 512²)",
    )
    p.add_argument(
        "--fits",
        action="store_true",
        help="D and G fitted to BEM curves of synthetic surfaces (D = 1.3, 1.5, 1.7; --realisations seeds each, "
        "l_min = L/16 on 64²) by the BEM model and by each comparator, without and with the surface's own "
        "characterisation as prior",
    )
    p.add_argument(
        "--fit-models",
        default=None,
        help="with --fits: the fitted models, comma-separated, of bem, persson, gw, 'xia2024 sneddon', "
        "'xia2024 none' (default: all)",
    )
    p.add_argument(
        "--plasticity",
        nargs="+",
        type=float,
        metavar="H",
        help="the validation table against the BEM with the pressure capped at each hardness H (Pa), "
        "on --grid (256 advised) with jaxcontact.BEM",
    )
    p.add_argument(
        "--substrate",
        choices=("periodic", "free", "mirrored"),
        help="half-space for a measured map (--topography): the map repeated as it is (periodic), alone on an "
        "infinite half-space (free: its K measures the map's size above ~1 %% contact), or repeated with its "
        "mirror images (mirrored: periodic without an edge step, twice the side)",
    )
    p.add_argument(
        "--no-fit", dest="fit", action="store_false", help="with --topography: skip the fits to the BEM curve"
    )


def progress(args, total_label: str):
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


def cache(args):
    from ..bem import ResultCache

    return None if args.no_cache else ResultCache(args.cache_dir)


def compare_spec(args):
    from ._scenefile import load_scene

    if args.scene is None:
        import importlib.resources

        path = importlib.resources.files("jaxcontact").joinpath("scenes", DEFAULT_COMPARE_SCENE)
        return load_scene(str(path))
    return load_scene(args.scene)


def comparison_table(rows, labels) -> str:
    """The ratios K_model / K_BEM, one column per label; a point without a valid value shows its
    status, whole (a column is as wide as its longest status)."""
    from ..studies._compare import column_key

    keys = [column_key(label) for label in labels]
    widths = [
        max(15, len(label), *(len(row[f"status_{key}"]) for row in rows if row[f"status_{key}"] != "ok"))
        for label, key in zip(labels, keys)
    ]

    def cell(row, key, width):
        status = row[f"status_{key}"]
        return f"{row['ratio_' + key]:>{width}.3g}" if status == "ok" else f"{status:>{width}}"

    head = f"{'F*':>10} {'A_r/A_a':>8} {'K*_BEM':>10} " + " ".join(
        f"{label:>{width}}" for label, width in zip(labels, widths)
    )
    lines = [head]
    for row in rows:
        cells = " ".join(cell(row, key, width) for key, width in zip(keys, widths))
        lines.append(f"{row['F_star']:>10.3g} {row['contact_fraction_bem']:>8.3%} {row['K_star_bem']:>10.4g} {cells}")
    return "\n".join(lines)


def plot_comparison(comparison, title, path) -> str:
    import numpy as np

    from ._plots import save_figure, subplots

    ref = comparison.reference
    unit_load = float(comparison.scene.material.E) * float(comparison.scene.area)
    unit_stiffness = float(comparison.scene.material.E) * math.sqrt(float(comparison.scene.area))
    from matplotlib.ticker import NullFormatter

    from ..studies._compare import model_curves

    F = ref.loads / unit_load
    # 32 loads: the load-array bucket of the table's own loads, so the plot compiles nothing new.
    fine = np.geomspace(ref.loads.min(), ref.loads.max(), 32)
    fig, ax = subplots(figsize=(6.5, 4.6))
    for label, (stiffness, _) in model_curves(comparison.scene, fine, comparison.compared).items():
        shown = np.isfinite(stiffness) & (stiffness > 0)
        note = "" if shown.all() else (" (flagged or K = 0 everywhere)" if not shown.any() else " (partly flagged)")
        ax.loglog(fine[shown] / unit_load, stiffness[shown] / unit_stiffness, "-", label=label + note)
    for label, (stiffness, _) in comparison.models.items():
        if label not in comparison.compared:  # a column of points (the map itself)
            ax.loglog(F, stiffness / unit_stiffness, "s", mfc="none", label=label)
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
