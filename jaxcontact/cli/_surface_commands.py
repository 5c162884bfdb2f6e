"""`jaxcontact surface FILE` and the topography front end of `jaxcontact run --topography FILE`."""

from __future__ import annotations

import importlib.resources
import math
import pathlib
import re

from ._output import print_result
from ._scenefile import DEFAULT_SCENE

# docs/validation.md: over L/l_min = 16…128 Persson's K stays within 0.92–1.06 of the elastic BEM on the
# same surface; GW grows as (L/l_min)^0.13–0.16 and the seed model as (L/l_min)^0.24–0.38 from it.
CLOSEST_TO_BEM = "persson"

# `--form`'s names: those of `topography._separate.FORMS` (a test checks), without importing it here.
FORMS = ("curvature", "tilt", "polynomial", "mean")


def add_topography_options(p) -> None:
    p.add_argument(
        "--tip-radius", type=float, help="stylus tip radius in m (default: the file's, or none: no reliability cutoff)"
    )
    p.add_argument(
        "--size",
        type=float,
        nargs="+",
        help="physical size in m: L for a line scan, LX LY for a map (default: the file's; given, it overrides it)",
    )
    p.add_argument(
        "--unit",
        choices=("m", "mm", "µm", "um", "nm"),
        help="unit of the heights (and of x in an x–z text profile) where the file gives none (default: m)",
    )
    p.add_argument(
        "--band",
        type=float,
        nargs=2,
        metavar=("SHORT", "LONG"),
        help="fit band, wavelengths in m (default: the widest band where the spectrum is a power law, found from "
        "the data; docs/topography.md)",
    )
    p.add_argument(
        "--fill-undefined",
        action="store_true",
        help="fill NaN or missing points by interpolation, up to 15 %% of them (default: refuse such a file)",
    )
    p.add_argument(
        "--form",
        choices=FORMS,
        default="curvature",
        help="the form removed before anything else: a quadric (curvature, the default, which the spectrum's "
        "estimate removes too), a plane (tilt), a polynomial of --form-degree, or the mean height alone",
    )
    p.add_argument("--form-degree", type=int, default=3, help="the degree of --form polynomial (1-10, default 3)")
    p.add_argument(
        "--waviness-cutoff",
        type=float,
        metavar="LAMBDA",
        help="split off wavelengths longer than LAMBDA (m) as waviness, by ISO 16610's Gaussian filter: the "
        "spectrum and the BEM see the roughness alone (default: no split)",
    )
    p.add_argument(
        "--groups",
        type=int,
        help="independent groups for the structure function's uncertainty (default: 16 blocks of line scans of "
        "a map, 8 segments of a profile)",
    )


def read_file(args, path):
    """Read `path` as the options say, its form removed and its waviness split off: the roughness, with
    what was removed in its `info["separation"]`."""
    from ..topography import Polynomial, read, separate
    from ..topography._separate import FORMS as KINDS

    size = None if args.size is None else (args.size[0] if len(args.size) == 1 else tuple(args.size))
    topography = read(path, size=size, unit=args.unit, tip_radius=args.tip_radius, fill_undefined=args.fill_undefined)
    form = Polynomial(args.form_degree) if args.form == "polynomial" else KINDS[args.form]()
    return separate(topography, form, args.waviness_cutoff).roughness


def characterise_file(args, method: str = "psd"):
    """Read and characterise `args.topography` (or `args.file`, its first) as the options say."""
    from ..topography import characterise

    path = args.file[0] if getattr(args, "file", None) else args.topography
    topography = read_file(args, path)
    return topography, characterise(topography, band=args.band, method=method, groups=args.groups)


def scene_text(characterisation, title: str) -> str:
    """A whole scene file: the default scene with its surface replaced by the characterised one."""
    from ..models import MODELS

    default = importlib.resources.files("jaxcontact").joinpath("scenes", DEFAULT_SCENE).read_text()
    rest = default[default.index("[material]") :]
    names = " | ".join(f'"{name}"' for name in MODELS)
    rest = re.sub(
        r"(?m)^name = .*$",
        f'name = "{CLOSEST_TO_BEM}"  # one of {names}; {CLOSEST_TO_BEM} is the closest to the '
        "boundary-element reference (docs/validation.md)",
        rest,
    )
    # The seed model's options; other models refuse them.
    rest = re.sub(r"(?m)^(interaction|distribution) = ", r"# (xia2024, jzz2010 only) \1 = ", rest)
    return f'title = "{title}"\n\n{characterisation.scene_fragment()}\n{rest}'


def describe(c) -> dict:
    """The JSON record of a characterisation: values, conventions named, intervals, diagnostics."""
    return {
        "method": c.method,
        "kind": c.kind.name,
        "D": c.D,
        "G_wm_m": c.G,
        "G_structure_function_m": c.G_structure_function,
        "l_min_m": c.l_min,
        "band_m": list(c.band),
        "stderr": {"D": c.stderr["D"], "G_wm_m": c.stderr["G"]},
        "ci95": {"D": list(c.ci95["D"]), "G_wm_m": list(c.ci95["G"])},
        "correlation_D_lnG": c.correlation,
        "groups": c.groups,
        "reliability_cutoff_m": c.reliability_cutoff,
        "band_ends": {"long": c.ends[0], "short": c.ends[1]},
        "rolloff_sigma_m": c.rolloff,
        "noise_floor": c.floor,
        "diagnostics": list(c.diagnostics),
    }


def summary_text(c, name: str) -> str:
    source = (
        f"{c.groups} measurements' spectra joined"
        if c.method == "psd" and c.groups > 1
        else f"the whole {c.kind.noun}'s spectrum"
        if c.method == "psd"
        else f"{c.groups} independent {c.kind.groups_noun}"
    )
    lines = [
        f"{name}: {c.kind.name} topography, {c.method} over wavelengths {c.band[0]:.4g}-{c.band[1]:.4g} m ({source})",
        *(f"  band's {end} end: {why}" for end, why in zip(("long", "short"), c.ends) if why),
        f"  D     = {c.D:.4f} ± {c.stderr['D']:.4f}   95 % [{c.ci95['D'][0]:.4f}, {c.ci95['D'][1]:.4f}]",
        f"  G     = {c.G:.4g} m (W-M convention, the model's) ×/÷ {math.exp(min(c.stderr['G'] / c.G, 700)):.3g}   "
        f"95 % [{c.ci95['G'][0]:.4g}, {c.ci95['G'][1]:.4g}] m",
        f"  G_sf  = {c.G_structure_function:.4g} m (structure-function convention, docs/model.md §8)",
        f"  l_min = {c.l_min:.4g} m (the band's short end; K depends on it)",
        f"  corr(D, ln G) = {c.correlation:+.3f}: G is extrapolated to q = 1 rad/m and moves with D",
    ]
    if c.reliability_cutoff:
        lines.append(f"  tip reliability cutoff: {c.reliability_cutoff:.4g} m")
    if c.rolloff:
        lines.append(f"  transfer function: a roll-off exp(-(qσ)²), σ = {c.rolloff:.3g} m, corrected in the band")
    if c.floor:
        lines.append(f"  noise floor: {c.floor:.3g} (spectrum units), subtracted")
    lines += [f"  diagnostic: {d}" for d in c.diagnostics]
    return "\n".join(lines)


def cmd_surface(args) -> int:
    from ..numerics import InputError
    from ..topography import NoBandError, characterise, compared
    from ._surface_plots import psd_figure, spectrum_figure

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if len(args.file) > 1:
        return _stitched(args, out)
    if args.accept_mismatch:
        raise InputError("--accept-mismatch applies to several files stitched; one file was given")
    try:
        topography, c = characterise_file(args)
    except NoBandError as exc:
        spectrum = (exc.spectrum.q, exc.spectrum.C)
        label = exc.spectrum.kind.psd_label
        path = psd_figure(spectrum, exc.local_slope, out / "psd.png", ylabel=label, suggestion=exc.suggestion)
        raise InputError(f"{exc}; wrote {path}") from None
    name = pathlib.Path(args.file[0]).name
    files = [
        psd_figure(
            c.spectrum,
            c.local_slope,
            out / "psd.png",
            ylabel=c.kind.psd_label,
            fit=c.fit,
            D=c.D,
            band=c.band,
            cutoff=c.reliability_cutoff,
        )
    ]
    notes = []
    try:
        sf = characterise(topography, method="structure-function", groups=args.groups)
        files.append(spectrum_figure(sf, "S(τ) (m²)", "τ (m)", out / "structure_function.png"))
        c = compared(c, sf)
    except InputError as exc:
        sf = None
        notes.append(f"structure function: {exc}")
    scene_path = out / "surface.toml"
    title = re.sub(r'["\\]', "", f"{name} ({c.kind.name}, {c.method} fit)")
    scene_path.write_text(scene_text(c, title))
    files.append(str(scene_path))
    text = summary_text(c, name) + f"\n  {topography.info['separation']}"
    if sf is not None:
        text += f"\n  structure function: D = {sf.D:.4f} ± {sf.stderr['D']:.4f}, G = {sf.G:.4g} m (W-M)"
    text += "".join(f"\n  {n}" for n in notes) + "\n\n" + "\n".join(f"wrote {f}" for f in files)
    payload = {
        "file": str(args.file[0]),
        "separation": topography.info["separation"],
        "psd": describe(c),
        "structure_function": None if sf is None else describe(sf),
    }
    print_result({**payload, "notes": notes, "files": files}, args.format, text)
    return 0


def _stitched(args, out: pathlib.Path) -> int:
    """`surface FILE1 FILE2 ...`: one power law over the measurements' bands joined."""
    from ..numerics import InputError
    from ..topography import characterise_stitched
    from ._surface_plots import psd_figure_stitched

    if args.band is not None:
        raise InputError("--band applies to one file; stitched measurements each find their own band")
    c = characterise_stitched([read_file(args, path) for path in args.file], accept_mismatch=args.accept_mismatch)
    names = " + ".join(pathlib.Path(f).name for f in args.file)
    files = [psd_figure_stitched(c, out / "psd.png")]
    scene_path = out / "surface.toml"
    scene_path.write_text(scene_text(c, re.sub(r'["\\]', "", f"{names} (stitched psd fit)")))
    files.append(str(scene_path))
    text = summary_text(c, names) + "\n\n" + "\n".join(f"wrote {f}" for f in files)
    payload = {"files_in": [str(f) for f in args.file], "psd": describe(c), "files": files}
    print_result(payload, args.format, text)
    return 0
