"""`jaxcontact compare --topography FILE --substrate S`: the BEM on a measured map itself beside the
models on its characterised (D, G, l_min), and each model's own (D, G) fitted to the BEM curve.
Without `--substrate` the map is a sample of the joint's roughness (`_compare_joint`)."""

from __future__ import annotations

import dataclasses
import math

from ._compare_table import compare_spec, comparison_table, plot_comparison
from ._output import CommandError, print_result

# Contact fractions (Persson's) at which the measured map is loaded.
MEASURED_FRACTIONS = (0.005, 0.02, 0.05, 0.12)


def fits_to_curve(comparison, K_bem, ok):
    """Each model's (D, G) fitted to the BEM curve, beside the characterised values."""
    from jaxcontact.fitting import fit

    from ..studies._compare import COMPARED

    rows = []
    for label, options in COMPARED.items():
        scene = comparison.scene.with_model(**options)
        try:
            result = fit(comparison.loads[ok], K_bem[ok], scene, params=("D", "G"), n_starts=4)
            D, G, loss, success = result.values["D"], result.values["G"], result.loss, bool(result.success)
            warnings = "; ".join(result.warnings)
        except ValueError as exc:  # a curve the model cannot reach at all: said, not fatal
            D = G = loss = math.nan
            success, warnings = False, str(exc)
        rows.append(
            {"model": label, "D_fit": D, "G_fit_wm_m": G, "loss": loss, "success": success, "warnings": warnings}
        )
    return rows


def write_tables(out, rows, fits) -> list[str]:
    """comparison.csv and, where there are fits, fits.csv in `out`: the paths written."""
    from ._report import write_csv

    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "comparison.csv")
    if not fits:
        return [str(out / "comparison.csv")]
    write_csv(fits, out / "fits.csv")
    return [str(out / "comparison.csv"), str(out / "fits.csv")]


def fits_text(fits, c) -> str:
    """The fits' lines (nothing where there are none), beside the surface's own D and G."""
    if not fits:
        return ""
    fitted = "\n".join(
        f"  {f['model']:>16}: D = {f['D_fit']:.4f}, G = {f['G_fit_wm_m']:.4g} m (W-M)"
        + ("" if f["success"] and not f.get("warnings") else f"  [{f.get('warnings') or 'not converged'}]")
        for f in fits
    )
    own = f"the surface's own: D = {c.D:.4f}, G = {c.G:.4g} m"
    return f"\nD, G of each model fitted to the BEM curve ({own}):\n{fitted}\n"


# Below this exponent of K ∝ F^α the BEM's K on a map is more a smooth body's than a rough one's: a
# Hertz contact's grows as F^(1/3), a rough surface's about as F at light load (Persson). Measured over
# the contact fractions compare uses: 0.86-0.89 on synthetic maps, 1.05 on x3p-2 and 1.19 on metropro-1
# with their curvature removed; 0.52 on metropro-1 with its form left in, 0.71 with its tilt alone
# removed, 0.67 on a synthetic map on a paraboloid 20 times its rms high (docs/validation.md).
HERTZ_LIKE = 0.75
# A rough surface's exponent over those fractions, which `HERTZ_LIKE` sits 15 % below.
ROUGH = 0.875


def _on_grid(topography, grid):
    """The map coarsened by halving (Fourier truncation) until no side exceeds `grid` points."""
    from ..bem import coarsened

    factor = 1
    while max(topography.nb_grid_pts) > grid and all(n % 2 == 0 for n in topography.nb_grid_pts):
        topography, factor = coarsened(topography), factor * 2
    return topography, factor


def exponent(loads, stiffness) -> float:
    """α of K ∝ F^α, least squares in log-log."""
    import numpy as np

    return float(np.polyfit(np.log(loads), np.log(stiffness), 1)[0])


def form_note(loads, stiffness, rough: float | None = None) -> str | None:
    """A line when the BEM's K on the map grows as F^α with α < `HERTZ_LIKE` (over its valid points),
    or, given `rough` (α of the same roughness without form: realisations of the map's spectrum at
    the same loads), with α < `HERTZ_LIKE` / `ROUGH` times it: nearer a smooth body's law than a
    rough one's."""
    if len(loads) < 2:
        return None
    alpha = exponent(loads, stiffness)
    if alpha >= (HERTZ_LIKE if rough is None else HERTZ_LIKE / ROUGH * rough):
        return None
    than = "a rough surface's (about F^0.85-1.2 at these contact fractions)"
    if rough is not None:
        than = f"the BEM's on realisations of its spectrum (F^{rough:.2f})"
    return (
        f"note: K_BEM ∝ F^{alpha:.2f} on this map, nearer a smooth body's law (Hertz: F^0.33) than {than}: the "
        "map's form or waviness carries the load; remove more of it (--form polynomial --form-degree N, "
        "--waviness-cutoff LAMBDA)"
    )


# What a free substrate's K is of: the map, not the joint.
FREE_WORDS = (
    ", the map alone on a free half-space: its K measures the map's own size (it tends to a flat punch of "
    "the map's side as contact grows), not the joint's; --substrate mirrored for a periodic map"
)


def compare_measured(args, out, cache, progress) -> int:
    import equinox as eqx
    import numpy as np

    from ..bem import SUBSTRATES, ReferenceCurves, bem_stiffness
    from ..studies._compare import Comparison, loads_for_fractions, model_curves
    from ..topography import mirrored
    from ._surface_commands import characterise_file

    topography, c = characterise_file(args)
    separation = topography.info["separation"]
    if topography.dim != 2:
        raise CommandError(f"{args.topography} is a line scan: the BEM needs an areal map")
    topography, coarsening = _on_grid(topography, args.grid)
    spec = compare_spec(args)
    lx, ly = topography.physical_sizes
    # The models see the surface the BEM sees: no wavelength shorter than the (coarsened) grid holds.
    l_min = max(c.l_min, 2 * lx / topography.nb_grid_pts[0])
    surface = eqx.tree_at(lambda s: s.l_min, c.surface, l_min)
    scene = eqx.tree_at(lambda s: (s.surface, s.area), spec.scene, (surface, np.asarray(lx * ly)))
    loads = loads_for_fractions(scene, MEASURED_FRACTIONS)
    if args.substrate == "mirrored":
        # Four copies of the map at four times its load: K of the map's own area is a quarter.
        mirror = mirrored(topography)
        result = bem_stiffness(mirror, float(scene.material.E), 4 * loads, cache=cache, progress=progress)
        result = dataclasses.replace(result, loads=loads, stiffness=result.stiffness / 4)
    else:
        substrate = SUBSTRATES[args.substrate]()
        result = bem_stiffness(
            topography, float(scene.material.E), loads, substrate=substrate, cache=cache, progress=progress
        )
    # One measured surface: no spread over realisations, no grid check.
    reference = ReferenceCurves((result,), seeds=(0,), grid=result.grid[0], convergence=None)
    comparison = Comparison(scene, reference, model_curves(scene, loads))
    if not reference.ok.any():
        raise CommandError("the BEM gave no valid point on this map (see comparison.csv's status)")
    rows = comparison.rows()
    notes = [note for note in [form_note(loads[reference.ok], result.stiffness[reference.ok])] if note]
    fits = fits_to_curve(comparison, result.stiffness, reference.ok) if args.fit else []
    files = write_tables(out, rows, fits)
    title = f"{args.topography}: D = {c.D:.4f}, G = {c.G:.4g} m (W-M), l_min = {c.l_min:.4g} m"
    files.append(plot_comparison(comparison, title, out / "comparison.png"))
    summary = (
        f"{title}\nK_model / K_BEM (BEM on the measured heights, {result.grid[0]} x {result.grid[1]}"
        + (f", coarsened {coarsening}x to --grid {args.grid}" if coarsening > 1 else "")
        + (", the map and its mirror images: a periodic map of twice its side" if args.substrate == "mirrored" else "")
        + (FREE_WORDS if args.substrate == "free" else "")
        + f")\n{separation}\n"
        f"{comparison_table(rows, list(comparison.models))}\n"
        + fits_text(fits, c)
        + "".join(f"{n}\n" for n in notes)
        + "\n".join(f"wrote {f}" for f in files)
    )
    payload = {"title": title, "separation": separation, "notes": notes, "rows": rows, "fits": fits}
    print_result(payload | {"files": files}, args.format, summary)
    return 0
