"""`jaxcontact fit`: a stiffness curve's D and G (or other parameters), with what the curve determines,
profiles, a prior from a measured surface or stated, and a posterior by NUTS."""

from __future__ import annotations

import pathlib

from ._output import EXIT_NOT_USABLE, CommandError, print_result


def cmd_fit(args) -> int:
    import sys
    import time

    import numpy as np

    from jaxcontact import fitting

    from ._report import scene_record
    from ._scenefile import load_scene

    if not 1 <= args.starts <= 1024:
        raise CommandError(f"--starts {args.starts} must be an integer in [1, 1024]")
    for option, value in (("--draws", args.draws), ("--seed", args.seed)):
        if value is not None and not args.posterior:
            raise CommandError(f"{option} {value} applies with --posterior only: add --posterior, or leave it out")
    if args.seed is not None and args.seed < 0:
        raise CommandError(f"--seed {args.seed} must be an integer >= 0")
    spec = load_scene(args.scene)
    curve = fitting.load_curve(args.data, spec.scene)
    t = time.perf_counter()
    if args.progress:
        print(
            f"fitting {args.params} to {curve.loads.size} points by {args.method} ({args.starts} starts); the first "
            "fit of a model compiles it (~10 s), later runs read it from the cache ...",
            file=sys.stderr,
            flush=True,
        )
    prior = _prior(args)
    result = fitting.fit(
        curve.loads,
        curve.stiffness,
        spec.scene,
        params=args.params,
        method=fitting.METHODS[args.method](),
        n_starts=args.starts,
        prior=prior,
        noise=args.noise,
        profile=True,
    )
    if args.progress:
        print(f"fit done in {time.perf_counter() - t:.1f} s", file=sys.stderr, flush=True)
    out = pathlib.Path(args.out)
    fine = np.geomspace(curve.loads.min(), curve.loads.max(), 200)
    # Through the fit's own compiled program: the fitted curve costs no new trace.
    fitted = fitting.model_stiffness(result.scene, result.params, fine)
    from ._plots import plot_fit

    files = [plot_fit(result, curve.loads, curve.stiffness, fine, fitted, out / "fit.png")]
    summary = result.summary()
    posterior = None
    if args.posterior:
        from ._posterior_plots import corner, posterior_band

        try:
            posterior = fitting.sample(
                curve.loads,
                curve.stiffness,
                spec.scene,
                args.params,
                prior=prior,
                noise=args.noise,
                draws=500 if args.draws is None else args.draws,
                seed=args.seed or 0,
            )
        except KeyboardInterrupt:
            # The least-squares fit is done: interrupting the sampler must not lose it.
            print(f"{curve.source}: {curve.loads.size} points\n{summary}\n(the posterior was interrupted)", flush=True)
            raise
        files += [
            corner(posterior, out / "corner.png"),
            posterior_band(posterior, curve.loads, curve.stiffness, out / "posterior_band.png"),
        ]
        summary += "\n" + posterior.summary()
    text = f"{curve.source}: {curve.loads.size} points, scene {spec.title}\n{summary}\n" + "\n".join(
        f"wrote {f}" for f in files
    )
    record = {"data": curve.source, "scene": scene_record(spec), **result.to_dict(), "files": files}
    if posterior is not None:
        record["posterior"] = posterior.to_dict()
    print_result(record, args.format, text)
    # 1: the fit ran and wrote its files, but its result is not usable (docs/cli.md, exit codes).
    usable = result.success and result.describes_data and (posterior is None or posterior.success)
    return 0 if usable else EXIT_NOT_USABLE


def _prior(args):
    """The fit's prior: the characterised `--topography`, or the `--prior` options, or None."""
    from jaxcontact import fitting

    if args.topography and args.prior:
        raise CommandError("give --topography or --prior, not both")
    if args.topography:
        from ._surface_commands import characterise_file

        return characterise_file(args)[1]
    if not args.prior:
        return None
    stated = {}
    for text in args.prior:
        name, _, value = text.partition("=")
        if name.strip() in stated:
            raise CommandError(f"--prior {text}: {name.strip()} has a prior already; give one per parameter")
        bounded = ".." in value
        try:
            first, second = (float(v) for v in value.split(".." if bounded else ":"))
        except ValueError:
            raise CommandError(f"--prior {text}: write NAME=MEAN:SD or NAME=LOW..HIGH (e.g. D=1.45:0.05)") from None
        try:
            stated[name.strip()] = (fitting.Bounds if bounded else fitting.Normal)(first, second)
        except ValueError as error:
            raise CommandError(f"--prior {text}: {error}") from None
    return stated
