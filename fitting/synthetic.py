"""Synthetic stiffness curves: the model's own curve with stated multiplicative noise.

Used for `data/table1_grinding_generated.csv` (labelled as generated, not measured) and for the
recovery and coverage tests.
"""

from __future__ import annotations

import numpy as np

import jaxcontact as jc


def synthetic_curve(scene: jc.Scene, F_star, noise: float = 0.05, seed: int = 0):
    """Loads (N) and stiffness (N/m): `K_model · exp(noise · N(0, 1))` at each `F*`.

    Raises `ValueError` if the model flags any of the loads (a generated curve must be valid).
    """
    loads = np.asarray(F_star, dtype=float) * float(scene.material.E) * float(scene.area)
    sol = jc.solve(scene, loads)
    if np.any(np.asarray(sol.status) != 0):
        bad = [f"{F:.3g} N ({jc.status_message(s)})" for F, s in zip(loads, np.asarray(sol.status)) if s]
        raise ValueError(f"the model flags loads of the synthetic curve: {', '.join(bad[:5])}")
    rng = np.random.default_rng(seed)
    return loads, np.asarray(sol.stiffness) * np.exp(noise * rng.standard_normal(loads.size))


TABLE1_SEED = 2024
TABLE1_F_STAR = np.geomspace(1e-10, 1e-4, 40)


def table1_generated(scene: jc.Scene):
    """The curve of `data/table1_grinding_generated.csv`: 40 loads, F* 1e-10…1e-4, 5 % noise.

    The curve reaches down to F* = 1e-10 on purpose: above F* ≈ 1e-7 every large spot is plastic
    and D and G trade off almost perfectly (correlation 0.999), and curves that stop at 1e-9
    leave a second (D, G) optimum within 1.5 % rms of the truth (a_c near the cutoff l_min²).
    """
    return synthetic_curve(scene, TABLE1_F_STAR, noise=0.05, seed=TABLE1_SEED)


TABLE1_COMMENTS = (
    "GENERATED data, not measured: jaxcontact's xia2024 model (interaction 'paper', distribution 'mb')",
    "on the Table 1 grinding surface (D = 1.4058, G = 2.2826e-10 m, E = 220 GPa, nu = 0.25, H = 100 GPa,",
    "A_a = 1e-4 m^2, l_min = 1e-9 m), 40 loads log-spaced over F* = 1e-10 ... 1e-4, stiffness multiplied",
    "by exp(0.05 N(0,1)) (5 % log-normal noise), numpy default_rng seed 2024.",
    "Regenerate with: python -c 'import fitting.synthetic as s; s.write_table1()'",
)


def write_table1(path="data/table1_grinding_generated.csv"):
    import jax

    from .data import write_curve
    from jaxcontact.scenefile import load_scene

    jax.config.update("jax_enable_x64", True)
    scene = load_scene().scene
    write_curve(path, *table1_generated(scene), comments=TABLE1_COMMENTS)
