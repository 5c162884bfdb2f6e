"""`jaxcontact validate-spectrum FILE ...`: the measured spectrum as the models' input against the BEM on
realisations of it, per file (`jaxcontact.studies.spectrum_validation`), as CSV and a table."""

from __future__ import annotations

import pathlib

from ._output import CommandError, print_result

COLUMNS = (
    "file",
    "contact_fraction_bem",
    "K_bem_N_per_m",
    "K_bem_spread",
    "map_bem_over_bem",
    "persson_spectrum_over_bem",
    "spectrum_band_low_over_bem",
    "spectrum_band_high_over_bem",
    "gw_spectrum_over_bem",
    "persson_power_law_over_bem",
    "power_law_band_low_over_bem",
    "power_law_band_high_over_bem",
    "status",
)


def register(command, common) -> None:
    """The subcommand, with the parser's own `command` and `common` helpers."""
    p = command(
        "validate-spectrum",
        "Persson and GW on a map's measured spectrum, and the power-law route, against the BEM on periodic "
        "realisations of that spectrum, at 0.5-15 %% contact",
    )
    p.add_argument("file", nargs="+", help="areal topography files (line scans are reported and skipped)")
    p.add_argument("--grid", type=int, default=128, help="BEM grid points a side, a power of two (default 128)")
    p.add_argument("--realisations", type=int, default=3, help="BEM realisations of each spectrum (default 3)")
    common(p, "jaxcontact-out/validate-spectrum")
    p.set_defaults(func=cmd_validate_spectrum)


def cmd_validate_spectrum(args) -> int:
    from ..studies._spectrum_validation import SpectrumSkipped, spectrum_validation
    from ._report import format_table, write_csv

    if args.realisations < 1:
        raise CommandError(f"--realisations {args.realisations} must be at least 1")
    rows, skipped = [], []
    for path in args.file:
        try:
            rows += spectrum_validation(path, grid=args.grid, realisations=args.realisations)
        except SpectrumSkipped as reason:
            skipped.append(f"{pathlib.Path(path).name}: skipped: {reason}")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    if rows:
        write_csv(rows, out / "spectrum_validation.csv")
        files.append(str(out / "spectrum_validation.csv"))
    text = (
        f"K_model / K_BEM (BEM on {args.realisations} periodic realisations of each map's measured spectrum, "
        f"{args.grid}²)\n"
        + (format_table(rows, COLUMNS) if rows else "no file could be used")
        + "".join(f"\n{line}" for line in skipped)
        + "".join(f"\nwrote {f}" for f in files)
    )
    print_result({"rows": rows, "skipped": skipped, "files": files}, args.format, text)
    return 0
