"""K against the short-wavelength cutoff: every model beside the boundary-element contact as l_min
shrinks at a fixed side L and load (docs/validation.md, "Scale"), and each one's trend in L/l_min."""

from __future__ import annotations

import math

import numpy as np

from ._compare import VALIDATION_D, column_key, loads_for_fractions
from ._plasticity import elastic_curves

# Elastic throughout: the BEM, and the seed model with every spot below a_c (`elastic_curves`).
SCALE_MODELS = {
    "xia2024 none": dict(model="xia2024", interaction="none"),
    "xia2024 sneddon": dict(model="xia2024", interaction="none", spot_stiffness="sneddon"),
    "gw": dict(model="gw"),
    "persson": dict(model="persson"),
}
DIVISIONS = (16, 32, 64, 128)


def scale_rows(
    scene,
    *,
    Ds=VALIDATION_D,
    divisions=DIVISIONS,
    fraction: float = 0.03,
    realisations: int = 2,
    seed: int = 0,
    progress=None,
) -> list[dict]:
    """K of the BEM and of each model of `SCALE_MODELS` at one load per D, as l_min = L/n shrinks.

    **Arguments:** `scene` (its E, ν, G and A_a = L²; D and l_min are replaced, and the models are
    evaluated with every spot elastic), `Ds`, `divisions` (the values of n = L/l_min; the BEM's grid is
    4n), `fraction` (the load is where Persson's contact area is this fraction of A_a at the
    coarsest l_min, held fixed as l_min shrinks), `realisations`, `seed` (of `jc.BEM`, with the
    reference's surfaces), `progress` (called as `progress(done, total)`).

    **Returns:** one dict per (D, n): `D`, `divisions`, `F_N`, `F_star`, `K_bem_N_per_m` (the mean over
    the realisations) with `K_bem_min_N_per_m` and `K_bem_max_N_per_m`, `contact_fraction_bem`, and per
    model `K_<model>_N_per_m`, `ratio_<model>` (K_model / K_BEM) and `ratio_<model>_low`/`_high` (against
    the realisations one at a time).
    """
    import equinox as eqx

    from ..bem import BEM
    from ..bem import solve as bem_solve
    from ..bem._solver import REFERENCE_STEP

    size = math.sqrt(float(scene.area))
    unit_load = float(scene.material.E) * float(scene.area)
    rows, done, total = [], 0, len(Ds) * len(divisions)
    for D in Ds:
        load = None
        for n in sorted(divisions):
            at = eqx.tree_at(
                lambda s: (s.surface.D, s.surface.l_min), scene, tuple(np.asarray(x, float) for x in (D, size / n))
            )
            if load is None:
                load = loads_for_fractions(at, (fraction,))
            model = BEM(grid=4 * n, realisations=realisations, seed=seed, rolloff=0.0, relative_step=REFERENCE_STEP)
            # Each realisation on its own (the model's secant, `bem.solve` on its surfaces): the mean
            # is the model's K, and the spread says how far one realisation is from another.
            each = [
                bem_solve(h, size, scene.material.E, load, secant=model.relative_step)
                for h in np.asarray(model.heights(at))
            ]
            Ks = np.array([float(np.asarray(b.secant_stiffness)[0]) for b in each])
            K_bem = float(np.mean(Ks))
            row = {
                "D": D,
                "divisions": n,
                "F_N": float(load[0]),
                "F_star": float(load[0]) / unit_load,
                "K_bem_N_per_m": K_bem,
                "K_bem_min_N_per_m": float(np.min(Ks)),
                "K_bem_max_N_per_m": float(np.max(Ks)),
                "contact_fraction_bem": float(np.mean([np.asarray(b.contact_fraction)[0] for b in each])),
            }
            for label, (stiffness, status) in elastic_curves(at, load, SCALE_MODELS).items():
                K = float(stiffness[0]) if status[0] == 0 else float("nan")
                key = column_key(label)
                row[f"K_{key}_N_per_m"] = K
                row[f"ratio_{key}"] = K / K_bem
                # Against the realisations one at a time: the band one measured surface would give.
                row[f"ratio_{key}_low"], row[f"ratio_{key}_high"] = K / float(np.max(Ks)), K / float(np.min(Ks))
            rows.append(row)
            done += 1
            if progress is not None:
                progress(done, total)
    return rows


def trend(rows, column: str) -> dict:
    """Per D, the exponent β of `column ∝ (L/l_min)^β` (least squares in log–log over the rows)."""
    out = {}
    for D in sorted({r["D"] for r in rows}):
        n = np.array([r["divisions"] for r in rows if r["D"] == D], float)
        y = np.array([r[column] for r in rows if r["D"] == D], float)
        keep = np.isfinite(y) & (y > 0)
        out[D] = float(np.polyfit(np.log(n[keep]), np.log(y[keep]), 1)[0]) if keep.sum() >= 2 else float("nan")
    return out


def scale_table(rows) -> str:
    """`rows` as text, with each column's exponent in L/l_min per D underneath."""
    labels = [column_key(label) for label in SCALE_MODELS]
    lines = [
        f"{'D':>4} {'L/l_min':>7} {'F*':>9} {'A_r/A_a':>8} {'K_BEM (N/m)':>12} "
        + " ".join(f"{label:>22}" for label in labels)
        + "   (K_model / K_BEM: over the realisations' mean (over each one alone))"
    ]
    for r in rows:
        ratios = [
            f"{r['ratio_' + k]:.3g} ({r['ratio_' + k + '_low']:.3g}–{r['ratio_' + k + '_high']:.3g})" for k in labels
        ]
        lines.append(
            f"{r['D']:>4} {r['divisions']:>7} {r['F_star']:>9.3g} {r['contact_fraction_bem']:>8.2%} "
            f"{r['K_bem_N_per_m']:>12.4g} " + " ".join(f"{x:>22}" for x in ratios)
        )
    exponents = {"bem": trend(rows, "K_bem_N_per_m")} | {k: trend(rows, f"K_{k}_N_per_m") for k in labels}
    lines.append("exponent β of K ∝ (L/l_min)^β:")
    for D in exponents["bem"]:
        lines.append(f"  D = {D}: " + ", ".join(f"{k} {v[D]:+.3f}" for k, v in exponents.items()))
    return "\n".join(lines)
