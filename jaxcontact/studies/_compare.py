"""Every model of the joint beside the elastic boundary-element reference (docs/model.md §9–10).

`compare_scene` synthesises realisations of a scene's surface (A_a = L²), solves the BEM at the
loads and evaluates each model of `COMPARED` on the same (D, G, l_min) and material;
`validation_rows` does it over D = 1.3, 1.5, 1.7 at loads spanning contact fractions 0.5–20 %.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

# Each model, by the label the tables use, and its name and options for `Scene.with_model`.
COMPARED = {
    "xia2024 paper": dict(model="xia2024", interaction="paper"),
    "xia2024 series": dict(model="xia2024", interaction="series"),
    "xia2024 none": dict(model="xia2024", interaction="none"),
    "xia2024 sneddon": dict(model="xia2024", interaction="none", spot_stiffness="sneddon"),
    "jzz2010": dict(model="jzz2010"),
    "gw": dict(model="gw"),
    "persson": dict(model="persson"),
}
VALIDATION_D = (1.3, 1.5, 1.7)
# Loads are set by Persson's contact area, which lies below the BEM's: the BEM's fractions then span ~0.5–20 %.
VALIDATION_FRACTIONS = (0.004, 0.03, 0.12)


def column_key(label: str) -> str:
    """A model's label as its CSV columns spell it ("xia2024 none" → "xia2024_none")."""
    return label.replace(" ", "_")


@dataclasses.dataclass(frozen=True)
class Comparison:
    """Models and the BEM reference at the same loads: `reference` (`bem.ReferenceCurves`),
    `models` (label → (stiffness N/m, status)), `scene`; `compared`, the models that a curve
    re-solves (label → `Scene.with_model` options; a label of `models` not among them is a column
    of points only)."""

    scene: object
    reference: object
    models: dict
    compared: dict = dataclasses.field(default_factory=lambda: COMPARED)

    @property
    def loads(self):
        return self.reference.loads

    def ratios(self) -> dict:
        """`K_model / K_BEM` (the realisations' mean), per model."""
        return {label: stiffness / self.reference.mean for label, (stiffness, _) in self.models.items()}

    def rows(self) -> list[dict]:
        """One row per load: F, F*, the BEM's contact fraction, mean and spread, each model's K and ratio."""
        from ..quantities import status_message

        ref = self.reference
        unit_load = float(self.scene.material.E) * float(self.scene.area)
        unit_stiffness = float(self.scene.material.E) * math.sqrt(float(self.scene.area))
        rows = []
        for i, load in enumerate(ref.loads):
            row = {
                "F_N": float(load),
                "F_star": float(load) / unit_load,
                "contact_fraction_bem": float(ref.contact_fraction[i]),
                "K_bem_mean_N_per_m": float(ref.mean[i]),
                "K_bem_low_N_per_m": float(ref.low[i]),
                "K_bem_high_N_per_m": float(ref.high[i]),
                "K_star_bem": float(ref.mean[i]) / unit_stiffness,
            }
            if ref.grid_change is not None:
                row["bem_grid_half_change"] = float(ref.grid_change[i])
            for label, (stiffness, status) in self.models.items():
                key = column_key(label)
                row[f"K_{key}_N_per_m"] = float(stiffness[i])
                row[f"ratio_{key}"] = float(stiffness[i]) / float(ref.mean[i])
                row[f"status_{key}"] = status_message(status[i])
            rows.append(row)
        return rows


def model_curves(scene, loads, models=COMPARED) -> dict:
    """Each model's K(F) on the scene's surface and material: label → (stiffness, status)."""
    from ..core import solve

    curves = {}
    for label, options in models.items():
        # `solve`'s default outputs: each model's program is the one `solve` and `run` compile (and keep).
        solution = solve(scene.with_model(**options), np.asarray(loads, dtype=float))
        curves[label] = (np.asarray(solution.stiffness), np.asarray(solution.status))
    return curves


def loads_for_fractions(scene, fractions, spectrum=None) -> np.ndarray:
    """Loads (N) at which Persson's theory puts the real contact area at `fractions` of A_a
    (`A_r/A_a = erf(w(q1) p/E)`, so `p = E erf⁻¹(A_r/A_a)/w(q1)`), on the scene's surface or on a
    measured `spectrum`."""
    from scipy.special import erfinv

    from ..core import solve
    from ..models import Persson

    unit = float(scene.material.E) * float(scene.area)
    probe = 1e-6
    persson = scene.with_model("persson" if spectrum is None else Persson(spectrum=spectrum))
    area = float(solve(persson, probe * unit).real_area) / float(scene.area)
    w1 = float(erfinv(area)) / probe
    return np.array([erfinv(f) / w1 * unit for f in fractions])


def compare_scene(scene, loads, **reference_options) -> Comparison:
    """The BEM reference of `scene` at `loads` (`bem.reference_curves` and its options) beside every model."""
    from ..bem import reference_curves

    reference = reference_curves(scene, loads, **reference_options)
    return Comparison(scene, reference, model_curves(scene, reference.loads))


def validation_rows(scene, *, Ds=VALIDATION_D, fractions=VALIDATION_FRACTIONS, **reference_options) -> list[dict]:
    """The validation table: for each D, `K_model/K_BEM` at loads spanning the contact fractions.

    Each row carries D, the load, the BEM's contact fraction and its spread (`K_BEM` low and high
    over the realisations), and one ratio per model (against the mean).
    """
    import equinox as eqx

    rows = []
    for D in Ds:
        at_D = eqx.tree_at(lambda s: s.surface.D, scene, np.asarray(D, dtype=float))
        comparison = compare_scene(at_D, loads_for_fractions(at_D, fractions), **reference_options)
        for row in comparison.rows():
            rows.append({"D": D, **row})
    return rows
