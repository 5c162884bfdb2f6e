"""Does a stiffness curve determine D when the model is right? D and G fitted with the boundary-element
model to noisy BEM curves of synthetic surfaces of known D, beside the same fits with the
comparators (docs/validation.md, "What a curve determines")."""

from __future__ import annotations

import math
import time

import numpy as np

from ._compare import VALIDATION_D, loads_for_fractions
from ._plasticity import elastic

FIT_MODELS = {
    "bem": None,  # the BEM model with the data's own seed: the right model
    "persson": dict(model="persson"),
    "gw": dict(model="gw"),
    "xia2024 sneddon": dict(model="xia2024", interaction="none", spot_stiffness="sneddon"),
    "xia2024 none": dict(model="xia2024", interaction="none"),
}


def bem_fit_rows(
    scene,
    *,
    Ds=VALIDATION_D,
    seeds=range(5),
    divisions: int = 16,
    loads: int = 8,
    fractions=(0.005, 0.15),
    noise: float = 0.03,
    start=(1.4, 3.0),
    progress=None,
) -> list[dict]:
    """For each D and seed: an elastic BEM curve of that realisation (grid 4·`divisions`, l_min = L/divisions,
    `loads` loads where Persson's contact area spans `fractions`, log-normal noise of sd `noise`),
    fitted for D and G by each model of `FIT_MODELS` (LM, Latin-hypercube starts beside D = `start[0]`,
    G = `start[1]` × the true G; the seed model with every spot elastic, `elastic`).

    **Returns:** one dict per (D, seed, model): `D_true`, `seed`, `model`, `D`, `D_low`, `D_high`
    (the 95 % interval), `covered`, `G_ratio` (fitted over true G), `success`, `seconds`,
    `describes_data`.
    """
    import warnings

    from ..numerics._validate import PlausibilityWarning

    # The seed model's elastic limit is a hardness far below what metals have (`elastic`).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        return _fit_rows(scene, Ds, seeds, divisions, loads, fractions, noise, start, progress)


def _fit_rows(scene, Ds, seeds, divisions, loads, fractions, noise, start, progress) -> list[dict]:
    import equinox as eqx

    import fitting

    from ..bem import BEM
    from ..core import solve

    size = math.sqrt(float(scene.area))
    G_true = float(scene.surface.G)
    rows, done, total = [], 0, len(Ds) * len(seeds)
    for D in Ds:
        values = tuple(np.asarray(x, float) for x in (D, size / divisions))
        truth = elastic(eqx.tree_at(lambda s: (s.surface.D, s.surface.l_min), scene, values))
        F = loads_for_fractions(truth, np.geomspace(*fractions, loads))
        for seed in seeds:
            right = BEM(grid=4 * divisions, realisations=1, seed=seed)
            clean = np.asarray(solve(truth.with_model(right), F).stiffness)
            K = clean * np.exp(noise * np.random.default_rng(seed).standard_normal(len(F)))
            for label, options in FIT_MODELS.items():
                model_scene = truth.with_model(right) if options is None else truth.with_model(**options)
                begin = eqx.tree_at(
                    lambda s: (s.surface.D, s.surface.G),
                    model_scene,
                    (np.asarray(start[0], float), np.asarray(start[1] * G_true, float)),
                )
                t = time.perf_counter()
                starts = 4 if options is None else 8  # the BEM's fits are the costly ones
                result = fitting.fit(F, K, begin, params=("D", "G"), method="lm", n_starts=starts)
                low, high = result.ci95["D"]
                rows.append(
                    {
                        "D_true": D,
                        "seed": seed,
                        "model": label,
                        "D": result.values["D"],
                        "D_low": low,
                        "D_high": high,
                        "covered": bool(low <= D <= high),
                        "G_ratio": result.values["G"] / G_true,
                        "success": bool(result.success),
                        "describes_data": bool(result.describes_data),
                        "seconds": time.perf_counter() - t,
                    }
                )
            done += 1
            if progress is not None:
                progress(done, total)
    return rows


def bem_fit_table(rows) -> str:
    """Per true D and model: the mean fitted D, the mean half-width of its interval, the coverage."""
    lines = [f"{'D':>4} {'model':>16} {'D fitted: mean (min–max)':>26} {'± (95 %)':>9} {'coverage':>9}"]
    for D in sorted({r["D_true"] for r in rows}):
        for label in FIT_MODELS:
            sel = [r for r in rows if r["D_true"] == D and r["model"] == label]
            values = np.array([r["D"] for r in sel])
            half = np.array([(r["D_high"] - r["D_low"]) / 2 for r in sel])
            covered = sum(r["covered"] for r in sel)
            lines.append(
                f"{D:>4} {label:>16} {values.mean():>10.3f} ({values.min():.3f}–{values.max():.3f})"
                f"{np.nanmean(half) if np.isfinite(half).any() else float('nan'):>9.3f} {covered:>5}/{len(sel)}"
            )
    return "\n".join(lines)
