"""A `Scene`: the joint (surface, material, nominal area) and the model to apply to it."""

from __future__ import annotations

import warnings

import equinox as eqx

from ..models import AbstractContactModel, build_model
from ..numerics._validate import InputError, PlausibilityWarning, as_array, check_instance, concrete
from ..quantities import PARAMETERS, implausible
from ..quantities._parameters import Material, Parameter, Surface


class Scene(eqx.Module):
    """The joint: its surface, material and nominal area, and the contact model to apply to it.

    **Arguments:**

    - `surface`: the `Surface` (D, G, l_min).
    - `material`: the `Material` (E, ν, H).
    - `area`: nominal contact area `A_a`, m², with `l_min² < area`.
    - `model`: the contact model, an object: `Xia2024()` (Xia, Qu & Liu 2024, the default, with its
      choices as arguments, `Xia2024(interaction=SeriesInteraction())`), `JZZ2010()`,
      `GreenwoodWilliamson()`, `Persson()` or any `AbstractContactModel`; or its name with the
      options by name, as scene files write them (`model="jzz2010"`, `interaction="series"`,
      `quadrature="gauss-legendre"`, `quadrature_nodes=32`, ...), which `jaxcontact.build_model`
      maps to the object.

    How to solve and what to return are options of `solve`, not of the scene. Float fields (of
    `surface`, `material` and `area`) are JAX arrays, pytree leaves: differentiate with
    `eqx.filter_grad` or `jax.grad` through `eqx.tree_at`, batch with `jax.vmap`. The model is
    static: changing it compiles a different program.
    """

    surface: Surface
    material: Material
    area: Parameter
    model: AbstractContactModel

    def __init__(
        self, surface: Surface, material: Material, area, model: AbstractContactModel | str = "xia2024", **options
    ):
        if not isinstance(surface, Surface):
            raise InputError(f"surface must be a jaxcontact.Surface, got {type(surface).__name__}")
        if not isinstance(material, Material):
            raise InputError(f"material must be a jaxcontact.Material, got {type(material).__name__}")
        self.surface = surface
        self.material = material
        self.area = as_array(area)
        self.model = _model(model, options)

    def with_model(self, model: AbstractContactModel | str, **options) -> Scene:
        """The same joint with another model: an object, or a name and its options by name. A
        name starts from that model's own defaults; nothing of this scene's model is carried over."""
        return Scene(self.surface, self.material, self.area, model, **options)

    def __check_init__(self):
        PARAMETERS["area"].check(self.area)
        l_min, area = concrete(self.surface.l_min), concrete(self.area)
        if l_min is not None and area is not None and not (l_min**2 < area).all():
            raise InputError(
                f"l_min = {l_min} m is too large for area = {area} m²: l_min² must be smaller than the nominal area"
            )
        for message in implausible(self):
            # A unit mistake (E in GPa) gives NaN with a status, not an error: say so where it is made.
            warnings.warn(message, PlausibilityWarning, stacklevel=3)


def _model(model, options: dict) -> AbstractContactModel:
    """The model object: given, or built by the registry from its name and options."""
    if isinstance(model, str):
        return build_model(model, **options)
    if options:
        raise InputError(f"{', '.join(options)} given beside the model object {model!r}: pass them to the model")
    check_instance("model", model, AbstractContactModel)
    return model


def stack_scenes(scenes) -> Scene:
    """Stack scenes that differ only in float values into one batched scene (for `jax.vmap`).

    Every float field becomes an array with a leading batch axis; the static choices must agree.
    """
    import jax
    import jax.numpy as jnp

    scenes = list(scenes)
    if not scenes:
        raise InputError("stack_scenes needs at least one scene")
    structures = {jax.tree.structure(s) for s in scenes}
    if len(structures) != 1:
        raise InputError("stack_scenes: the scenes differ in their model or its choices")
    return jax.tree.map(lambda *xs: jnp.stack([jnp.asarray(x) for x in xs]), *scenes)
