"""Synthetic stiffness curves: the model's own curve with stated multiplicative noise.

Used for `data/table1_grinding_generated.csv` (labelled as generated, not measured) and for the
recovery and coverage tests.
"""

from __future__ import annotations

import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.core import table1_values


def synthetic_curve(scene: jc.Scene, F_star, noise: float = 0.05, seed: int = 0):
    """Loads (N) and stiffness (N/m): `K_model · exp(noise · N(0, 1))` at each `F*`.

    Raises `ValueError` if the model flags any of the loads (a generated curve must be valid).
    """
    loads = np.asarray(F_star, dtype=float) * float(jc.Scales.of(scene).load)
    sol = jc.solve(scene, loads)
    if np.any(np.asarray(sol.status) != 0):
        bad = [f"{F:.3g} N ({jc.status_message(s)})" for F, s in zip(loads, np.asarray(sol.status)) if s]
        raise InputError(f"the model flags loads of the synthetic curve: {', '.join(bad[:5])}")
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


def table1_comments() -> tuple[str, ...]:
    """The header of `data/table1_grinding_generated.csv`: what it is and how it was made."""
    v = table1_values()
    return (
        "GENERATED data, not measured: jaxcontact's xia2024 model (interaction 'paper', distribution 'mb')",
        f"on the Table 1 grinding surface (D = {v['D']:g}, G = {v['G']:g} m, E = {v['E'] / 1e9:g} GPa, "
        f"nu = {v['nu']:g}, H = {v['H'] / 1e9:g} GPa,",
        f"A_a = {v['area']:g} m^2, l_min = {v['l_min']:g} m), 40 loads log-spaced over F* = 1e-10 ... 1e-4, "
        "stiffness multiplied",
        f"by exp(0.05 N(0,1)) (5 % log-normal noise), numpy default_rng seed {TABLE1_SEED}.",
        "Regenerate with: python -c 'from jaxcontact.fitting._synthetic import write_table1; write_table1()'",
    )


def write_table1(path="data/table1_grinding_generated.csv"):
    import jax

    from ._data import write_curve

    jax.config.update("jax_enable_x64", True)
    scene = jc.table1_scene()
    write_curve(path, *table1_generated(scene), comments=table1_comments())
