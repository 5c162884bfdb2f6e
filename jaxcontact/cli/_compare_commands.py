"""`jaxcontact compare`: every model beside the elastic boundary-element reference (docs/model.md §9–10)."""

from __future__ import annotations

import pathlib

from ._compare_table import cache, compare_spec, comparison_table, plot_comparison, progress
from ._output import CommandError, print_result


def cmd_compare(args) -> int:
    from ..numerics._validate import optional_import
    from ..studies._compare import COMPARED, compare_scene, validation_rows
    from ._report import write_csv

    # Before any work: ContactMechanics for its reference (and for measured maps, which may not be
    # square), SurfaceTopography for the synthesised surfaces either way.
    optional_import("SurfaceTopography", "jaxcontact compare's surfaces")
    if args.topography or args.reference == "contactmechanics":
        optional_import("ContactMechanics", "the boundary-element reference of jaxcontact compare")

    out = pathlib.Path(args.out)
    if args.topography and args.substrate is None:  # the joint's roughness: realisations of the map's spectrum
        from ._compare_joint import compare_joint

        return compare_joint(args, out, cache(args))
    if args.topography:  # the map itself
        from ._compare_measured import compare_measured

        return compare_measured(args, out, cache(args), progress(args, "BEM"))
    if args.seed < 0:
        raise CommandError(f"--seed {args.seed} must be an integer >= 0")
    studies = [f"--{name}" for name in ("plasticity", "scale", "fits", "validation") if getattr(args, name)]
    if len(studies) > 1:
        raise CommandError(f"{' and '.join(studies)}: give one study at a time")
    spec = compare_spec(args)
    options = dict(
        grid=args.grid, realisations=args.realisations, seed=args.seed, cache=cache(args), reference=args.reference
    )
    labels = list(COMPARED)
    command = f"--grid {args.grid} --realisations {args.realisations} --seed {args.seed}"
    if args.plasticity:
        from ..studies._plasticity import plasticity_rows, plasticity_table

        for H in args.plasticity:
            if not H > 0:
                raise CommandError(f"--plasticity H = {H} must be a hardness in Pa, > 0")
        rows = plasticity_rows(
            spec.scene,
            hardnesses=tuple(args.plasticity),
            grid=args.grid,
            realisations=args.realisations,
            seed=args.seed,
            progress=progress(args, "BEM"),
        )
        hardnesses = " ".join(f"{H:g}" for H in args.plasticity)
        return _table(args, out, rows, "plasticity.csv", f"--plasticity {hardnesses} {command}", plasticity_table(rows))
    if args.scale:
        from ..studies._scale import scale_rows, scale_table

        rows = scale_rows(spec.scene, realisations=args.realisations, seed=args.seed, progress=progress(args, "BEM"))
        flags = f"--scale --realisations {args.realisations} --seed {args.seed}"
        return _table(args, out, rows, "scale.csv", flags, scale_table(rows))
    if args.fits:
        from ..studies._bem_fits import bem_fit_rows, bem_fit_table, fit_models

        seeds = range(args.seed, args.seed + args.realisations)
        models = fit_models(args.fit_models)
        rows = bem_fit_rows(spec.scene, seeds=seeds, models=models, progress=progress(args, "curves"))
        flags = f"--fits --realisations {args.realisations} --seed {args.seed}"
        if args.fit_models is not None:
            flags += f" --fit-models '{','.join(models)}'"
        return _table(args, out, rows, "fits.csv", flags, bem_fit_table(rows))
    if args.validation:
        rows = validation_rows(spec.scene, progress=progress(args, "BEM"), convergence=False, **options)
        by_D = sorted({r["D"] for r in rows})
        text = "\n\n".join(f"D = {D}\n" + comparison_table([r for r in rows if r["D"] == D], labels) for D in by_D)
        return _table(args, out, rows, "validation.csv", f"--validation {command}", text)
    comparison = compare_scene(spec.scene, spec.loads, progress=progress(args, "BEM"), **options)
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
        f"{comparison_table(rows, labels)}\n{convergence}\n" + "\n".join(f"wrote {f}" for f in files)
    )
    print_result({"title": spec.title, "rows": rows, "files": files}, args.format, summary)
    return 0


def _table(args, out: pathlib.Path, rows, name: str, options: str, text: str) -> int:
    from ._report import write_csv

    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / name, comments=[f"jaxcontact compare {options}"])
    files = [str(out / name)]
    print_result({"rows": rows, "files": files}, args.format, f"{text}\n\nwrote {files[0]}")
    return 0
