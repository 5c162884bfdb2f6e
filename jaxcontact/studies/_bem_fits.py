"""Does a stiffness curve determine D when the model is right, and what does it add to the measured
surface? D and G fitted with the boundary-element model to noisy BEM curves of synthetic surfaces of
known D, beside the same fits with the comparators, each without and with the surface's own
characterisation as a prior (docs/fitting.md, "What the curve adds to the surface")."""

from __future__ import annotations

import math
import time

import numpy as np

from ..numerics import InputError
from ._compare import VALIDATION_D, loads_for_fractions
from ._plasticity import elastic

FIT_MODELS = {
    "bem": None,  # the BEM model with the data's own seed: the right model
    "persson": dict(model="persson"),
    "gw": dict(model="gw"),
    "xia2024 sneddon": dict(model="xia2024", interaction="none", spot_stiffness="sneddon"),
    "xia2024 none": dict(model="xia2024", interaction="none"),
}


def fit_models(names: str | None) -> tuple[str, ...]:
    """The labels of `FIT_MODELS` named in `names`, the command line's `--fit-models` (comma-separated;
    None: all of them)."""
    if names is None:
        return tuple(FIT_MODELS)
    chosen = tuple(name.strip() for name in names.split(","))
    unknown = [name for name in chosen if name not in FIT_MODELS]
    if unknown or not chosen:
        raise InputError(f"--fit-models {names!r}: each must be one of {', '.join(FIT_MODELS)}")
    return chosen


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
    priors=(False, True),
    models=tuple(FIT_MODELS),
    progress=None,
) -> list[dict]:
    """For each D and seed: an elastic BEM curve of that realisation (grid 4·`divisions`, l_min = L/divisions,
    `loads` loads where Persson's contact area spans `fractions`, log-normal noise of sd `noise`),
    fitted for D and G by each model of `FIT_MODELS` (LM, Latin-hypercube starts beside D = `start[0]`,
    G = `start[1]` × the true G; the seed model with every spot elastic, `elastic`), once alone and
    once (`priors` holding True) with the prior of the same surface's map characterised
    (`topography.characterise`, in its spectrum's coordinates; the fit starts at its estimate, the BEM
    model's from 2 starts instead of 4). `models`: the labels of `FIT_MODELS` fitted. A map whose
    spectrum has no power-law band (`topography.NoBandError`) has no prior: its surface columns are
    NaN and its fits with a prior are left out.

    **Returns:** one dict per (D, seed, model, prior): `D_true`, `seed`, `model`, `prior`, `D`, `D_low`,
    `D_high` (the 95 % interval), `covered`, `G_ratio` (fitted over true G), `G_covered`, `success`,
    `on_bound` (the fit ended on a search bound, and so is not a success), `seconds`, `describes_data`;
    and the surface's own `D_surface`, `D_surface_low`, `D_surface_high`, `G_surface_ratio`,
    `G_surface_covered`.
    """
    import warnings

    from ..numerics._validate import PlausibilityWarning

    # The seed model's elastic limit is a hardness far below what metals have (`elastic`).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        return _fit_rows(scene, Ds, seeds, divisions, loads, fractions, noise, start, priors, models, progress)


def surface_map(scene, model):
    """The map of the BEM model's first realisation of the scene's surface, as an instrument would give it
    (a periodic SurfaceTopography `Topography` in m), heights exactly those the model solves."""
    import SurfaceTopography as st

    size = math.sqrt(float(scene.area))
    heights = np.asarray(model.heights(scene)[0], float)
    return st.Topography(heights, (size, size), periodic=True, unit="m")


def _own(surface, G_true) -> dict:
    """The characterised map's own D and G against the truth (NaN without a power-law band)."""
    if surface is None:
        nan = dict.fromkeys(("D_surface", "D_surface_low", "D_surface_high", "G_surface_ratio"), math.nan)
        return nan | {"G_surface_covered": False}
    G_low, G_high = surface.ci95["G"]
    return {
        "D_surface": surface.D,
        "D_surface_low": surface.ci95["D"][0],
        "D_surface_high": surface.ci95["D"][1],
        "G_surface_ratio": surface.G / G_true,
        "G_surface_covered": bool(G_low <= G_true <= G_high),
    }


def study_truth(scene, D: float, divisions: int = 16, loads: int = 8, fractions=(0.005, 0.15)):
    """The study's elastic surface of dimension `D` (l_min = L/`divisions`) from `scene`, and its
    `loads` loads (N) where Persson's contact area spans `fractions`."""
    import warnings

    import equinox as eqx

    from ..numerics._validate import PlausibilityWarning

    size = math.sqrt(float(scene.area))
    values = tuple(np.asarray(x, float) for x in (D, size / divisions))
    # The seed model's elastic limit is a hardness far below what metals have (`elastic`).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        truth = elastic(eqx.tree_at(lambda s: (s.surface.D, s.surface.l_min), scene, values))
        return truth, loads_for_fractions(truth, np.geomspace(*fractions, loads))


def _fit_rows(scene, Ds, seeds, divisions, loads, fractions, noise, start, priors, models, progress) -> list[dict]:
    import equinox as eqx

    from jaxcontact import fitting

    from ..bem import BEM
    from ..core import solve
    from ..topography import NoBandError, characterise

    G_true = float(scene.surface.G)
    rows, done, total = [], 0, len(Ds) * len(seeds)
    for D in Ds:
        truth, F = study_truth(scene, D, divisions, loads, fractions)
        for seed in seeds:
            right = BEM(grid=4 * divisions, realisations=1, seed=seed)
            clean = np.asarray(solve(truth.with_model(right), F).stiffness)
            K = clean * np.exp(noise * np.random.default_rng(seed).standard_normal(len(F)))
            try:
                surface = characterise(surface_map(truth, right))
            except NoBandError:
                surface = None
            own = _own(surface, G_true)
            for label in models:
                options = FIT_MODELS[label]
                model_scene = truth.with_model(right) if options is None else truth.with_model(**options)
                for prior in priors if surface is not None else [p for p in priors if not p]:
                    begin = (start[0], start[1] * G_true) if not prior else (surface.D, surface.G)
                    begin = eqx.tree_at(
                        lambda s: (s.surface.D, s.surface.G), model_scene, tuple(np.asarray(x, float) for x in begin)
                    )
                    t = time.perf_counter()
                    # The BEM's fits are the costly ones; with a prior its mean is the first start.
                    starts = (2 if prior else 4) if options is None else 8
                    result = fitting.fit(
                        F,
                        K,
                        begin,
                        params=("D", "G"),
                        method=fitting.LevenbergMarquardt(),
                        n_starts=starts,
                        prior=surface if prior else None,
                    )
                    low, high = result.ci95["D"]
                    G_low, G_high = result.ci95["G"]
                    rows.append(
                        {
                            "D_true": D,
                            "seed": seed,
                            "model": label,
                            "prior": prior,
                            "D": result.values["D"],
                            "D_low": low,
                            "D_high": high,
                            "covered": bool(low <= D <= high),
                            "G_ratio": result.values["G"] / G_true,
                            "G_covered": bool(G_low <= G_true <= G_high),
                            "success": bool(result.success),
                            "on_bound": bool(result.on_bound),
                            "describes_data": bool(result.describes_data),
                            "seconds": time.perf_counter() - t,
                            **own,
                        }
                    )
            done += 1
            if progress is not None:
                progress(done, total)
    return rows


def bem_fit_table(rows) -> str:
    """Per true D, model and prior: the mean fitted D, the mean half-width of its interval, the coverage
    of D and of G; and per D the surface's own characterisation."""
    lines = [
        f"{'D':>4} {'model':>16} {'prior':>6} {'D fitted: mean (min–max)':>26} {'± (95 %)':>9} "
        f"{'describes':>10} {'D covered':>10} {'G covered':>10} {'success':>8} {'on bound':>9}"
    ]
    for D in sorted({r["D_true"] for r in rows}):
        first = [r for r in {r["seed"]: r for r in rows if r["D_true"] == D}.values() if np.isfinite(r["D_surface"])]
        values = np.array([r["D_surface"] for r in first])
        half = np.array([(r["D_surface_high"] - r["D_surface_low"]) / 2 for r in first])
        covered = sum(r["D_surface_low"] <= D <= r["D_surface_high"] for r in first)
        if not first:
            lines.append(f"{D:>4} {'surface alone':>16} {'–':>6}   no map with a power-law band")
        else:
            lines.append(
                f"{D:>4} {'surface alone':>16} {'–':>6} {values.mean():>10.3f} ({values.min():.3f}–{values.max():.3f})"
                f"{np.nanmean(half):>9.3f} {'–':>10} {covered:>6}/{len(first)} "
                f"{sum(r['G_surface_covered'] for r in first):>6}/{len(first)} {'–':>8} {'–':>9}"
            )
        for label in [m for m in FIT_MODELS if any(r["model"] == m for r in rows)]:
            for prior in sorted({r["prior"] for r in rows}):
                sel = [r for r in rows if r["D_true"] == D and r["model"] == label and r["prior"] == prior]
                if not sel:  # no map of this D had a prior
                    continue
                values = np.array([r["D"] for r in sel])
                half = np.array([(r["D_high"] - r["D_low"]) / 2 for r in sel])
                lines.append(
                    f"{D:>4} {label:>16} {'yes' if prior else 'no':>6} {values.mean():>10.3f} "
                    f"({values.min():.3f}–{values.max():.3f})"
                    f"{np.nanmean(half) if np.isfinite(half).any() else float('nan'):>9.3f} "
                    f"{sum(r['describes_data'] for r in sel):>6}/{len(sel)} "
                    f"{sum(r['covered'] for r in sel):>6}/{len(sel)} "
                    f"{sum(r['G_covered'] for r in sel):>6}/{len(sel)} "
                    f"{sum(r['success'] for r in sel):>4}/{len(sel)} "
                    f"{sum(r.get('on_bound', False) for r in sel):>5}/{len(sel)}"
                )
    return "\n".join(lines)
