"""The scene in the paper's dimensionless variables (Sec. 5.1), in logs.

Areas in `A_a`, lengths in `sqrt(A_a)`, loads in `E A_a`, stiffness in `E sqrt(A_a)`:
`G* = G/sqrt(A_a)`, `H* = H/E`, `a* = a/A_a`. The smallest asperity `a_min* = l_min²/A_a` is
~1e-14 and `a^(-(D+2)/2)` there would overflow float32, so every area is carried as its log.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .asperity import hardness_coefficient, log_critical_area
from .distribution import log_density_scale
from .scene import Scene


class DimensionlessScene(eqx.Module):
    """Scale-free inputs of one scene.

    **Fields:** `D`; `log_G` = ln G*; `log_hardness` = ln(H/E); `kappa` = κ;
    `log_a_c` = ln a_c* (Eq. 7); `log_a_min` = ln(l_min²/A_a); `log_density` = ln of the size
    distribution's correction factor (0 for "mb").
    """

    D: Float[Array, ""]
    log_G: Float[Array, ""]
    log_hardness: Float[Array, ""]
    kappa: Float[Array, ""]
    log_a_c: Float[Array, ""]
    log_a_min: Float[Array, ""]
    log_density: Float[Array, ""]


def nondimensionalise(scene: Scene) -> DimensionlessScene:
    """The scene's dimensionless groups (MODEL.md §1)."""
    s, m = scene.surface, scene.material
    D = jnp.asarray(s.D)
    log_sqrt_area = 0.5 * jnp.log(scene.area)
    log_G = jnp.log(s.G) - log_sqrt_area
    log_hardness = jnp.log(m.H) - jnp.log(m.E)
    kappa = hardness_coefficient(jnp.asarray(m.nu))
    log_phi = jnp.log(kappa / 2.0) + log_hardness  # φ = κH/(2E)
    return DimensionlessScene(
        D=D,
        log_G=log_G,
        log_hardness=log_hardness,
        kappa=kappa,
        log_a_c=log_critical_area(D, log_G, log_phi),
        log_a_min=2.0 * (jnp.log(s.l_min) - log_sqrt_area),
        log_density=log_density_scale(D, scene.distribution),
    )
