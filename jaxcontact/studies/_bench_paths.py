"""Benchmarks of load paths for `jaxcontact bench`: the capped BEM's and measured elastic–plastic
summits', each against the `solve` of the same loads (timings, nothing asserted)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..core import Scene, solve
from ._curve import called


def bem_path(scene: Scene, grid: int = 256) -> dict:
    """`bem.solve_path` of a 10-point load–unload path (five loads up to F* = 3e-3, five down) on a
    capped rough map (D = 1.5, rms slope ~0.15, H = 0.015 E*, `grid`²), as users call it, against
    `bem.solve` of the same ten loads: median and best of 5 calls after compilation (s)."""
    del scene  # the map is the BEM's own
    from .. import bem

    size = 100e-6
    modulus = 210e9 / (1 - 0.3**2)
    heights = jnp.asarray(bem.realisation(1.5, 1e-9, size / 64, size, grid, 0).heights())
    up = np.geomspace(3e-4, 3e-3, 5) * modulus * size * size
    path = jnp.asarray(np.concatenate([up, up[::-1][1:] * 0.9, [0.5 * up[0]]]))
    hardness = 0.015 * modulus
    along = called(lambda: bem.solve_path(heights, size, modulus, path, hardness=hardness).stiffness, repeats=5)
    apart = called(lambda: bem.solve(heights, size, modulus, path, hardness=hardness).stiffness, repeats=5)
    return {"path": along, "solve": apart, "over_solve": along["median_s"] / apart["median_s"]}


def summit_path(scene: Scene, points: int = 200) -> dict:
    """`jc.solve_path` of measured elastic–plastic summits (R = 0.1 mm, 1e9 per m², Gaussian heights
    of 0.3 µm rms on a 201-point table, H = 1 GPa, E = 100 GPa, 1 cm²) along a `points`-point path
    (load to 30 N, unload to 1 N, reload to 60 N), against `solve` of the same loads: median and best
    of 15 calls after compilation (s)."""
    from ..applications import solve_path
    from ..models import MeasuredAsperities
    from ..physics import KogutEtsionSummits
    from ..quantities import Material

    z = np.linspace(0.0, 2e-6, 201)
    model = MeasuredAsperities(1e-4, 1e9, z, np.exp(-0.5 * ((z - 0.8e-6) / 0.3e-6) ** 2), KogutEtsionSummits())
    joint = Scene(scene.surface, Material(E=1e11, nu=0.3, H=1e9), 1e-4, model=model)
    third = points // 3
    path = jnp.asarray(
        np.concatenate(
            [np.geomspace(0.3, 30, third), np.geomspace(30, 1, third)[1:], np.geomspace(1, 60, points - 2 * third + 1)]
        )
    )
    along = called(lambda: solve_path(joint, path).approach)
    apart = called(lambda: solve(joint, path).stiffness)
    return {"path": along, "solve": apart, "over_solve": along["median_s"] / apart["median_s"]}
