"""The validation table with a hardness: every model beside the boundary-element contact whose
pressure is capped at H (perfect plasticity, docs/model.md §10), and how each one's K moves from
its elastic value as H falls.

The seed model's spots are elastic below `a_c = G² (κH/2E)^(2/(1−D))` and plastic above it, so its
elastic limit is H → 0 (a_c above every spot), not H → ∞ (a_c → 0: every spot plastic)."""

from __future__ import annotations

import warnings

import numpy as np

from ._compare import COMPARED, VALIDATION_D, VALIDATION_FRACTIONS, column_key, loads_for_fractions, model_curves

# Models whose K depends on H (through a_c), and the elastic comparators beside them.
PLASTICITY_MODELS = {label: options for label, options in COMPARED.items() if label != "xia2024 paper"}
HARDNESSES = (1e10, 3e9, 1e9)
# The models' elastic reference: at this hardness a_c lies above A_a for D ≤ 1.7 on docs/model.md
# §10's surface (every spot of the seed model elastic; tests check it). Far below what metals have:
# the plausibility warning it raises is expected.
ELASTIC_HARDNESS = 1e4


def elastic(scene):
    """`scene` with H = `ELASTIC_HARDNESS`: every spot of the seed model elastic."""
    import equinox as eqx

    return eqx.tree_at(lambda s: s.material.H, scene, np.asarray(ELASTIC_HARDNESS, float))


def elastic_curves(scene, loads, models) -> dict:
    """`model_curves` with every spot elastic (`elastic`)."""
    from ..numerics._validate import PlausibilityWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        return model_curves(elastic(scene), loads, models)


def plasticity_rows(
    scene,
    *,
    hardnesses=HARDNESSES,
    Ds=VALIDATION_D,
    fractions=VALIDATION_FRACTIONS,
    grid: int = 256,
    realisations: int = 3,
    seed: int = 0,
    progress=None,
) -> list[dict]:
    """For each D, load and hardness: the capped BEM's K and its change from the elastic BEM, and for
    each model `K_model(H) / K_BEM(H)` and `K_model(H) / K_model(elastic) − 1`.

    **Arguments:** `scene` (its E, ν, A_a = L², G, l_min; D and H are replaced), `hardnesses` (Pa),
    `Ds`, `fractions` (loads where Persson's elastic contact area is these fractions of A_a),
    `grid`, `realisations`, `seed` (of `jc.BEM`, with the reference's surfaces: `rolloff=0`),
    `progress` (called as `progress(done, total)` over the (D, H) pairs).

    **Returns:** one dict per (D, load, H): `D`, `H_Pa`, `F_N`, `F_star`, `contact_fraction_bem`,
    `K_star_bem`, `bem_change` (K_BEM(H)/K_BEM(elastic) − 1), and per model `ratio_<model>` and
    `change_<model>` (NaN where a status is not ok).
    """
    import equinox as eqx

    from ..bem import BEM
    from ..bem._solver import REFERENCE_STEP
    from ..core import solve

    def with_values(base, D, H):
        return eqx.tree_at(lambda s: (s.surface.D, s.material.H), base, (np.asarray(D, float), np.asarray(H, float)))

    def bem_curve(at, plastic, loads):
        model = BEM(
            grid=grid, realisations=realisations, seed=seed, plastic=plastic, rolloff=0.0, relative_step=REFERENCE_STEP
        )
        solution = solve(at.with_model(model), loads)
        return np.asarray(solution.stiffness), np.asarray(solution.real_area) / float(at.area)

    unit_load = float(scene.material.E) * float(scene.area)
    unit_stiffness = float(scene.material.E) * float(np.sqrt(float(scene.area)))
    rows, done, total = [], 0, len(Ds) * (len(hardnesses) + 1)
    for D in Ds:
        at_D = with_values(scene, D, scene.material.H)
        loads = loads_for_fractions(at_D, fractions)
        bem_elastic, _ = bem_curve(at_D, False, loads)
        models_elastic = elastic_curves(at_D, loads, PLASTICITY_MODELS)
        done += 1
        if progress is not None:
            progress(done, total)
        for H in hardnesses:
            at = with_values(scene, D, H)
            bem_plastic, fraction = bem_curve(at, True, loads)
            models = model_curves(at, loads, PLASTICITY_MODELS)
            for i, load in enumerate(loads):
                row = {
                    "D": D,
                    "H_Pa": H,
                    "F_N": float(load),
                    "F_star": float(load) / unit_load,
                    "contact_fraction_bem": float(fraction[i]),
                    "K_star_bem": float(bem_plastic[i]) / unit_stiffness,
                    "bem_change": float(bem_plastic[i] / bem_elastic[i] - 1.0),
                }
                for label, (stiffness, status) in models.items():
                    elastic, elastic_status = models_elastic[label]
                    ok = status[i] == 0 and elastic_status[i] == 0
                    key = column_key(label)
                    row[f"ratio_{key}"] = float(stiffness[i] / bem_plastic[i]) if status[i] == 0 else float("nan")
                    usable = ok and elastic[i] > 0
                    row[f"change_{key}"] = float(stiffness[i] / elastic[i] - 1.0) if usable else float("nan")
                rows.append(row)
            done += 1
            if progress is not None:
                progress(done, total)
    return rows


def plasticity_table(rows) -> str:
    """`rows` as text: per D and H, the BEM's change and each model's change and ratio."""
    labels = [column_key(label) for label in PLASTICITY_MODELS]
    head = f"{'D':>4} {'H (Pa)':>8} {'F*':>9} {'A_r/A_a':>8} {'BEM ΔK':>8} " + " ".join(
        f"{label:>22}" for label in labels
    )
    lines = [head, " " * 41 + "  (each model: ΔK from its elastic K; K/K_BEM)"]
    for r in rows:
        cells = " ".join(f"{r['change_' + k]:>+11.1%} {r['ratio_' + k]:>10.3g}" for k in labels)
        lines.append(
            f"{r['D']:>4} {r['H_Pa']:>8.2g} {r['F_star']:>9.3g} {r['contact_fraction_bem']:>8.2%} "
            f"{r['bem_change']:>+8.1%} {cells}"
        )
    return "\n".join(lines)
