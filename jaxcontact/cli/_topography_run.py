"""`jaxcontact run --topography FILE`: from a measured surface to K(F) with the model chosen (by default
the one closest to the boundary-element reference), its 95 % band, and the other models beside it."""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np

# Models left out of the comparison, and why (each is a few minutes per curve, not seconds).
NOT_COMPARED = {"bem": "the boundary-element model solves the surface itself: jaxcontact compare --topography FILE"}
# The models that solve on a measured spectrum, and what the measured route gave against the BEM
# on realisations of the spectrum of the six real areal maps (docs/validation.md).
SPECTRUM_MODELS = ("persson", "gw")
MEASURED_AGREEMENT = {
    "persson": "0.74-1.13 of the BEM at 1.5-15 % contact, 0.62-0.85 at 0.5 % (128²-1024²)",
    "gw": "0.77-1.30 of the BEM at 0.5-5 % contact, 0.54-0.76 at 15 % or its summits exhausted (128²-1024²)",
}


def add_run_topography_options(p) -> None:
    from ..models import MODELS
    from ._surface_commands import CLOSEST_TO_BEM

    p.add_argument(
        "--model",
        choices=tuple(MODELS),
        help=f"the contact model (default with --topography: {CLOSEST_TO_BEM}, the closest to the boundary-element "
        "reference in docs/validation.md; without: the scene's)",
    )
    p.add_argument(
        "--route",
        choices=("spectrum", "power-law"),
        help="with --topography: the surface as its measured spectrum (default, for persson and gw) or as the "
        "power law fitted to it (D, G, l_min; the seed model and jzz2010 take only this)",
    )
    p.add_argument("--l-min", type=float, help="l_min in m (default: the fit band's short end, or the scene's)")
    p.add_argument("--modulus", type=float, help="contact modulus E in Pa (default: the scene's)")
    p.add_argument("--poisson", type=float, help="Poisson's ratio (default: the scene's)")
    p.add_argument("--hardness", type=float, help="hardness H in Pa (default: the scene's)")
    p.add_argument("--area", type=float, help="nominal contact area in m² (default: the scene's)")
    p.add_argument(
        "--stiffness",
        choices=("loading", "unloading", "tangential"),
        help="which K: the loading tangent (the paper's), the unloading (dynamic) one about each load, or "
        "Mindlin's tangential one in full stick (default: the scene's [effects] stiffness, else loading; "
        "docs/in-service.md)",
    )


def _scene(scene, model: str, surface, args):
    """The scene with the options' model, surface and material, built anew: the options' values get the
    checks and plausibility warnings that the same values in a scene file get."""
    from ..core import Scene
    from ..quantities import Material

    material = Material(
        E=scene.material.E if args.modulus is None else args.modulus,
        nu=scene.material.nu if args.poisson is None else args.poisson,
        H=scene.material.H if args.hardness is None else args.hardness,
    )
    area = scene.area if args.area is None else args.area
    # The scene's own model keeps the scene's options.
    return Scene(surface, material, area, model=scene.model if model == scene.model.name else model)


def zero_note(name: str, solution) -> str | None:
    """One line on why a model gives no stiffness at any load, or None if it gives some."""
    K, status = np.asarray(solution.stiffness), np.asarray(solution.status)
    if np.any((status == 0) & (K > 0)):
        return None
    if np.all(np.asarray(solution.fully_plastic) | (status != 0)) and np.any(solution.fully_plastic):
        return (
            f"{name}: K = 0 at every load: every contact spot is plastic at this l_min (its critical spot area "
            "exceeds the largest spot; Sec. 4.2): try --l-min or another --model"
        )
    from ..quantities import status_message

    return f"{name}: no value at any load ({status_message(int(status[status != 0][0]))})"


def _with_spectrum(scene, spectrum):
    """The scene's model (persson or gw) solving on `spectrum`."""
    import equinox as eqx

    return eqx.tree_at(lambda s: s.model.spectrum, scene, spectrum, is_leaf=lambda x: x is None)


def _characterised(args, spectrum_route: bool):
    """The file's topography, its characterisation and, where it has no power-law band and the route
    needs none, the `NoBandError` (whose `spectrum` is the map's whole) with the characterisation over
    the closest window it suggests; otherwise None."""
    from ..topography import NoBandError, characterise
    from ._surface_commands import read_file

    topography = read_file(args, args.topography)
    try:
        return topography, characterise(topography, band=args.band, groups=args.groups), None
    except NoBandError as none:
        if not spectrum_route or none.band is None or none.spectrum.kind.name != "areal":
            raise
        return topography, characterise(topography, band=none.band, groups=args.groups), none


def topography_run(spec, args):
    """The scene of `spec` on the characterised surface with the chosen model and material, K(F)'s 95 %
    band, the other models' solutions at the same loads (by name), and notes (one line each). On the
    spectrum route (the default) persson and gw solve on the measured spectrum and the band is its
    own (`spectrum_band`); on the power-law route every model has (D, G, l_min) and the band is
    theirs (`stiffness_band`)."""
    from ..core import solve
    from ..models import MODELS
    from ..physics import MeasuredSpectrum
    from ..quantities import Surface
    from ..topography import spectrum_band, stiffness_band
    from ._surface_commands import CLOSEST_TO_BEM

    model = args.model or CLOSEST_TO_BEM
    measured = (args.route or "spectrum") == "spectrum"
    topography, c, whole = _characterised(args, measured and model in SPECTRUM_MODELS)
    surface = Surface(D=c.D, G=c.G, l_min=c.l_min if args.l_min is None else args.l_min)
    spectrum = None
    if measured:
        shortest = float(surface.l_min)
        spectrum = (
            MeasuredSpectrum.from_characterisation(c, shortest=shortest)
            if whole is None
            else MeasuredSpectrum.from_binned(whole.spectrum, shortest=shortest)
        )
    scene = _scene(spec.scene, model, surface, args)
    name = pathlib.Path(args.topography).name
    fitted = f"D = {c.D:.4f}, G = {c.G:.4g} m (W-M)" + ("" if whole is None else " over the closest window")
    title = f"{name}: {fitted}, l_min = {surface.l_min:.4g} m; model {model}"
    why = " (the closest to the boundary-element reference, docs/validation.md; --model to choose)"
    notes = [f"model: {model}" + ("" if args.model else why), topography.info["separation"]]
    if measured and model in SPECTRUM_MODELS:
        scene = _with_spectrum(scene, spectrum)
        band = spectrum_band(scene, spec.loads)
        table = (
            "over the band"
            if whole is None
            else "of the whole map, from its longest wavelength to l_min: it has no power-law band, and D and G of "
            f"the closest window ({c.band[0]:.3g}-{c.band[1]:.3g} m) are not used"
        )
        notes.append(
            f"route: the measured spectrum ({spectrum.log_q.size} bins {table}; rolled off below; 95 % band "
            f"from each bin's uncertainty); on the real areal maps {model} on this route was "
            f"{MEASURED_AGREEMENT[model]} (docs/validation.md); --route power-law for D, G, l_min"
        )
    else:
        band = stiffness_band(c, scene, spec.loads)
        reason = f"{model} takes D, G, l_min only" if measured else "--route power-law"
        notes.append(f"route: the power law fitted to the spectrum ({reason}; 95 % band from D and G's covariance)")
    others = {}
    # On a map without a power-law band, the models that take D, G, l_min alone have no surface.
    no_band = "the map has no power-law band, and it takes D, G, l_min only"
    left_out = {
        k: NOT_COMPARED.get(k, no_band)
        for k in MODELS
        if k in NOT_COMPARED or (whole is not None and k not in SPECTRUM_MODELS)
    }
    for other in MODELS:
        if other == model or other in left_out:
            continue
        other_scene = _scene(spec.scene, other, surface, args)
        if measured and other in SPECTRUM_MODELS:
            other_scene = _with_spectrum(other_scene, spectrum)
        others[other] = solve(other_scene, spec.loads)
    notes += [note for note in (zero_note(k, solution) for k, solution in others.items()) if note]
    notes += [f"{k}: not compared: {why}" for k, why in left_out.items() if k != model]
    notes.append(form_check(topography, scene, spectrum))
    spec = dataclasses.replace(spec, scene=scene, title=title)
    return spec, band, others, notes


FORM_CHECK_GRID = 64  # the mirrored map is solved on twice this a side


def form_check(roughness, scene, spectrum) -> str:
    """One line on whether the map's form carries the load: the BEM on the map itself (mirrored,
    `FORM_CHECK_GRID`), at the loads where Persson puts 0.5-15 % of it in contact, grows as F^α;
    below 0.75 (`form_note`) the line says so and what to remove."""
    from ..studies._compare import loads_for_fractions
    from ..studies._spectrum_validation import FRACTIONS, mirrored_map_stiffness
    from ._compare_measured import exponent, form_note

    if roughness.dim != 2:
        return "form check: none for a line scan (the BEM needs an areal map)"
    loads = loads_for_fractions(scene, FRACTIONS, spectrum)
    K, _ = mirrored_map_stiffness(roughness, FORM_CHECK_GRID, float(scene.material.E), loads, float(scene.area))
    ok = np.isfinite(K) & (K > 0)
    if ok.sum() < 2:
        return "form check: the BEM on the map gave fewer than two values"
    alpha = exponent(loads[ok], K[ok])
    return form_note(loads[ok], K[ok]) or (
        f"form check: the BEM on the map itself (mirrored, {2 * FORM_CHECK_GRID}²) grows as K ∝ F^{alpha:.2f} at "
        "0.5-15 % contact, as a rough surface does"
    )


OVERRIDES = ("model", "l_min", "modulus", "poisson", "hardness", "area")


def overridden(spec, args):
    """`spec` with the model, l_min and material the options give (a run without --topography)."""
    from ..quantities import Surface

    if all(getattr(args, k, None) is None for k in OVERRIDES):
        return spec
    old = spec.scene.surface
    surface = Surface(D=old.D, G=old.G, l_min=old.l_min if args.l_min is None else args.l_min)
    return dataclasses.replace(spec, scene=_scene(spec.scene, args.model or spec.scene.model.name, surface, args))
