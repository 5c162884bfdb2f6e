"""Which stiffness a joint has in service (docs/in-service.md): the loading tangent of the paper, the
initial unloading tangent about a state reached by loading, and Mindlin's tangential stiffness in
full stick.

A spot of contact radius `r` on an elastic half-space has the normal stiffness `2E*r` (Sneddon) and,
in full stick, the tangential stiffness `8G*r` (Mindlin 1949; Johnson 1985, §7.2), whatever made it:
an elastic–plastic spot unloads elastically from its top with `2E*r` of its contact radius there
(Etsion, Kligerman & Kadin, IJSS 42, 3716, 2005). For two bodies of like material `G*` follows from
the joint's composite `E*` and Poisson's ratio ν: `G* = E* (1 − ν) / (2 (2 − ν))`, so that
`8G*r / (2E*r) = 2(1 − ν)/(2 − ν)` spot by spot (for a whole elastic rough contact too: Campañá,
Persson & Müser, JPCM 23, 085001, 2011). Unlike materials: `jaxcontact.contact_modulus` and
`tangential_contact_modulus`.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx


def mindlin_ratio(nu):
    """`K_t / K_n = 8G*/(2E*) = 2(1 − ν)/(2 − ν)` of a spot in full stick, two bodies of like material."""
    return 2.0 * (1.0 - nu) / (2.0 - nu)


class AbstractStiffness(eqx.Module):
    """Which stiffness `solve` returns (`Outputs(stiffness=...)`).

    **Class attributes:** `name` (reports, the command line), `unloading` (whether it is built on
    each spot's unloading stiffness at the state the load reaches on loading).
    """

    name: eqx.AbstractClassVar[str]
    unloading: eqx.AbstractClassVar[bool]

    @abc.abstractmethod
    def of_normal(self, normal, nu):
        """This stiffness from the normal one it is built on (loading or unloading), for Poisson's ratio ν."""


class Loading(AbstractStiffness):
    """The loading tangent `dF/dδ` (the paper's K, Eqs. 36–39): what `solve` has always returned."""

    name: ClassVar[str] = "loading"
    unloading: ClassVar[bool] = False

    def of_normal(self, normal, nu):
        return normal


class Unloading(AbstractStiffness):
    """The initial unloading tangent at the state the load reaches on loading: every spot unloads
    elastically, a spot that flowed with the elastic stiffness of its contact area at the top
    (Sneddon's `2E*r`, or the model's own elastic spot law); the dynamic stiffness of a small
    vibration about a preload. Equal to `Loading()` for an elastic model."""

    name: ClassVar[str] = "unloading"
    unloading: ClassVar[bool] = True

    def of_normal(self, normal, nu):
        return normal


class TangentialStick(AbstractStiffness):
    """Mindlin's tangential stiffness in full stick at the state the load reaches on loading: each
    spot's `8G*r`, i.e. `2(1 − ν)/(2 − ν)` times its unloading stiffness (like materials)."""

    name: ClassVar[str] = "tangential"
    unloading: ClassVar[bool] = True

    def of_normal(self, normal, nu):
        return normal * mindlin_ratio(nu)
