"""`jaxcontact compare --topography FILE` without `--substrate`: the map as a sample of the joint's
roughness (docs/validation.md). The BEM on periodic realisations of its measured spectrum (their
mean and spread) at loads of its own contact fractions; beside it, the BEM on the map itself and its
mirror images, Persson and GW on the measured spectrum, and every model on the power-law route (the
characterised D and G, l_min at the table's cut)."""

from __future__ import annotations

import pathlib

from ._compare_table import compare_spec, comparison_table, plot_comparison
from ._output import CommandError, print_result

MIRRORED = "mirrored map"
# The models that solve on the measured spectrum, by the labels the table gives them.
ON_THE_SPECTRUM = ("persson spectrum", "gw spectrum")


def _roughness(args):
    """The map, its form removed as the options say."""
    from ._surface_commands import read_file

    topography = read_file(args, args.topography)
    if topography.dim != 2:
        raise CommandError(f"{args.topography} is a line scan: the BEM needs an areal map")
    return topography


def _curve(args, cache, modulus):
    """`curve(topography, loads)` on a periodic map for `--reference contactmechanics`; None for
    `measured_joint`'s default, the JAX solve."""
    from ..bem import bem_stiffness

    if args.reference != "contactmechanics":
        return None
    return lambda topography, loads: bem_stiffness(topography, modulus, loads, cache=cache)


def compare_joint(args, out, cache) -> int:
    import numpy as np

    from ..models import GreenwoodWilliamson, Persson
    from ..quantities import status_message
    from ..studies._compare import COMPARED, Comparison, model_curves
    from ..studies._spectrum_validation import FRACTIONS, SpectrumSkipped, measured_joint
    from ._compare_measured import exponent, fits_text, fits_to_curve, form_note, write_tables

    if args.realisations < 1:
        raise CommandError(f"--realisations {args.realisations} must be at least 1")
    topography = _roughness(args)
    material = compare_spec(args).scene.material
    try:
        joint = measured_joint(
            topography,
            material,
            grid=args.grid,
            realisations=args.realisations,
            fractions=FRACTIONS,
            curve=_curve(args, cache, float(material.E)),
            band=args.band,
            groups=args.groups,
        )
    except SpectrumSkipped as reason:
        raise CommandError(f"{args.topography}: {reason}") from None
    spectrum, ref, c = joint.spectrum, joint.reference, joint.characterisation
    if not ref.ok.any():
        flagged = sorted({status_message(int(x)) for r in ref.results for x in r.status if x != 0})
        raise CommandError(
            f"the BEM gave no valid point on the realisations of the map's spectrum: {', '.join(flagged)}"
        )
    on_spectrum = dict(zip(ON_THE_SPECTRUM, (Persson(spectrum=spectrum), GreenwoodWilliamson(spectrum=spectrum))))
    compared = {label: dict(model=model) for label, model in on_spectrum.items()} | (COMPARED if c else {})
    models = model_curves(joint.scene, joint.loads, compared) | {MIRRORED: (joint.mirrored, joint.mirrored_status)}
    comparison = Comparison(joint.scene, ref, models, compared)
    rows = comparison.rows()
    shown = np.isfinite(joint.mirrored)
    rough = exponent(joint.loads[ref.ok], ref.mean[ref.ok]) if ref.ok.sum() > 1 else None
    notes = [note for note in [form_note(joint.loads[shown], joint.mirrored[shown], rough)] if note]
    # The power-law models' own D and G fitted to the realisations' mean curve.
    fits = fits_to_curve(comparison, ref.mean, ref.ok) if args.fit and c is not None else []
    files = write_tables(out, rows, fits)
    name = pathlib.Path(args.topography).name
    cut = float(joint.scene.surface.l_min)
    title = (
        f"{name}: no power-law band, the measured spectrum alone; its table to {cut:.4g} m"
        if c is None
        else f"{name}: D = {c.D:.4f}, G = {c.G:.4g} m (W-M); the table and l_min to {cut:.4g} m"
    )
    files.append(plot_comparison(comparison, title, out / "comparison.png"))
    spread = ref.stiffness.std(axis=0) / ref.mean
    separation = topography.info["separation"]
    header = (
        f"K_model / K_BEM (the BEM on {len(ref.seeds)} periodic realisations of the map's measured spectrum, "
        f"{ref.grid}², their spread {np.nanmin(spread):.0%}-{np.nanmax(spread):.0%}, at loads of its own contact "
        f"fractions; the joint the map's area)\n{', '.join(ON_THE_SPECTRUM)}: on the measured spectrum; "
        + ("" if c is None else "the others: on the power law (D, G, l_min); ")
        + f"{MIRRORED}: the BEM on the map itself and its mirror images (at most {2 * args.grid}²)"
    )
    summary = (
        f"{title}\n{header}\n{separation}\n"
        f"{comparison_table(rows, list(comparison.models))}\n"
        + fits_text(fits, c)
        + "".join(f"{n}\n" for n in notes)
        + "\n".join(f"wrote {f}" for f in files)
    )
    payload = {"title": title, "separation": separation, "notes": notes, "rows": rows, "fits": fits, "files": files}
    print_result(payload, args.format, summary)
    return 0
