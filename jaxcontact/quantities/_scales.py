"""Units: the scales that make a scene dimensionless (Sec. 5.1), and its dimensionless groups.

Areas in `A_a`, lengths in `sqrt(A_a)`, loads in `E A_a`, stiffness in `E sqrt(A_a)`:
`F* = F/(E A_a)`, `K* = K/(E sqrt(A_a))`, `G* = G/sqrt(A_a)`, `H* = H/E`, `a* = a/A_a`. The
smallest asperity `a_min* = l_min²/A_a` is ~1e-14 and `a^(-(D+2)/2)` there would overflow
float32, so every area is carried as its log.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from ..numerics._compat import namespace


class Scales(eqx.Module):
    """The units of the paper's dimensionless variables, from the modulus `E` (Pa) and the
    nominal area `A_a` (m²). Every conversion between SI and starred quantities goes through here.

    **Properties:** `load` = E A_a (N), `stiffness` = E sqrt(A_a) (N/m), `length` = sqrt(A_a) (m),
    and `area` itself (m²).
    """

    modulus: Float[ArrayLike, "*batch"]
    area: Float[ArrayLike, "*batch"]

    @classmethod
    def of(cls, scene) -> Scales:
        """The scales of a `Scene`."""
        return cls(scene.material.E, scene.area)

    @property
    def load(self):
        return self.modulus * self.area

    @property
    def stiffness(self):
        return self.modulus * self.length

    @property
    def length(self):
        return namespace(self.area).sqrt(self.area)


class DimensionlessScene(eqx.Module):
    """Scale-free inputs of one scene, common to every model.

    **Fields:** `D`; `log_G` = ln G*; `log_hardness` = ln(H/E); `nu` = ν; `log_a_min` =
    ln(l_min²/A_a); `log_length` = ln(√A_a / 1 m), the one dimensional number, for a model that
    carries lengths of its own (`MeasuredAsperities`). What a model derives from them (the
    Kogut–Etsion a_c, the PSD's moments) it derives itself (`physics.kogut_etsion_laws`, `physics._spectrum`).
    """

    D: Float[Array, ""]
    log_G: Float[Array, ""]
    log_hardness: Float[Array, ""]
    nu: Float[Array, ""]
    log_a_min: Float[Array, ""]
    log_length: Float[Array, ""]


def nondimensionalise(scene) -> DimensionlessScene:
    """The dimensionless groups of a `Scene` (docs/model.md §1)."""
    s, m = scene.surface, scene.material
    D = jnp.asarray(s.D)
    log_sqrt_area = 0.5 * jnp.log(scene.area)
    log_G = jnp.log(s.G) - log_sqrt_area
    return DimensionlessScene(
        D=D,
        log_G=log_G,
        log_hardness=jnp.log(m.H) - jnp.log(m.E),
        nu=jnp.asarray(m.nu),
        log_a_min=2.0 * (jnp.log(s.l_min) - log_sqrt_area),
        log_length=log_sqrt_area,
    )
