"""What the tests share: the embedded scenes' values, scene builders, masked sums, jitted helpers.
(Settings and fixtures live in conftest.py.)"""

import importlib.util
import os
import pathlib

import equinox as eqx
import jax
import jaxtyping
import pytest

import jaxcontact as jc
from jaxcontact.core import table1_values
from jaxcontact.quantities import nondimensionalise

ROOT = pathlib.Path(__file__).resolve().parents[1]

# Whether the library runs under jaxtyping's import hook with beartype (conftest.py,
# JAXCONTACT_TYPECHECK=1).
TYPECHECKED = os.environ.get("JAXCONTACT_TYPECHECK") == "1" and importlib.util.find_spec("beartype") is not None


def refused_type(parameter: str, message: str):
    """`pytest.raises` for an argument of the wrong type: the library's own `ValueError` matching
    `message`; under the type checker, which sees the call first, its error naming `parameter`."""
    if TYPECHECKED:
        return pytest.raises(jaxtyping.TypeCheckError, match=f"parameter '{parameter}'")
    return pytest.raises(ValueError, match=message)


SHARED = ROOT.parent / "shared"
# The 96 conformance vectors, shipped with the tests (tests/data/README.md), and the specification's
# own copy beside the project (absent in a user's clone).
CHECKPOINTS = ROOT / "tests" / "data" / "checkpoints.csv"
SHARED_CHECKPOINTS = SHARED / "checkpoints.csv"

# docs/model.md §7: Table 1 grinding surface with the paper's material values (the embedded default scene).
TABLE1 = table1_values()
# Sec. 5.1 material (Figs. 3–6).
SEC51 = dict(E=210e9, nu=0.3, H=120e9, area=1e-4, l_min=1e-9)
# Table 1 without interaction: the truth of the fits, the inference and the posteriors whose subject is
# not the interaction (their programs compile in a third of the time), and the wrong start they fit from.
TABLE1_WITHOUT_INTERACTION = dict(TABLE1, interaction="none")
WRONG_START = dict(TABLE1_WITHOUT_INTERACTION, D=1.55, G=1e-9)
# docs/model.md §10's surface for the comparators and the boundary-element reference: L = 100 µm,
# l_min = L/64, G = 1e-12 m, E = 210 GPa (data/scenes/bem_comparison.toml).
BEM_L = 100e-6
BEM_SETTING = dict(D=1.5, G=1e-12, E=210e9, nu=0.3, H=3e8, area=BEM_L * BEM_L, l_min=BEM_L / 64)


def make_scene(D, G, E, nu, H, area, l_min, model="xia2024", **options):
    """A scene of these values; `model` an object, or a name with its `options` by name."""
    return jc.Scene(jc.Surface(D=D, G=G, l_min=l_min), jc.Material(E=E, nu=nu, H=H), area, model, **options)


def make_joint(scene):
    """The dimensionless joint that the scene's (largest-spot) model solves."""
    return scene.model.joint(nondimensionalise(scene))


# Every float field of a scene, for differentiating with respect to all of them at once.
PARAMS = ("D", "G", "E", "H", "l_min", "nu", "area")
GETTERS = {name: jc.PARAMETERS[name].get for name in PARAMS}


def with_params(scene, values):
    """The scene with its float fields set to `values` (ordered as `PARAMS`)."""
    for name, v in zip(PARAMS, values):
        scene = eqx.tree_at(GETTERS[name], scene, v)
    return scene


def masked_log_stiffness_sum(sol, weights=1.0):
    """Σ w ln K over a solution's valid points: flagged points add exactly 0, to every derivative too."""
    ok = sol.ok
    return jax.numpy.sum(jax.numpy.where(ok, weights * jax.numpy.log(jax.numpy.where(ok, sol.stiffness, 1.0)), 0.0))


def _masked_log_stiffness(scene, loads, weights):
    sol = jc.solve(scene, loads)
    return masked_log_stiffness_sum(sol, weights), sol.status


_log_stiffness_and_gradient = eqx.filter_jit(eqx.filter_value_and_grad(_masked_log_stiffness, has_aux=True))
# Every call pads its loads to this many, so that the tests of several files that differentiate one
# model's Σ w ln K with respect to a whole scene share one compiled program.
GRADIENT_LOADS = 5


def log_stiffness_and_gradient(scene, loads, weights=None):
    """((Σ w ln K over the valid points, statuses), its gradient with respect to every leaf of
    `scene`) at up to `GRADIENT_LOADS` loads (weights default 1; the statuses of `loads` alone)."""
    loads = jax.numpy.asarray(loads, float)
    weights = jax.numpy.ones_like(loads) if weights is None else jax.numpy.asarray(weights, float)
    pad = GRADIENT_LOADS - loads.size
    assert pad >= 0, f"{loads.size} loads: the shared program takes at most {GRADIENT_LOADS}"
    # Padding: good loads of weight zero. Leaves as float64 arrays: Python floats would be weakly
    # typed and compile the program again.
    loads = jax.numpy.concatenate([loads, jax.numpy.full(pad, 22.0)])
    weights = jax.numpy.concatenate([weights, jax.numpy.zeros(pad)])
    scene = jax.tree.map(lambda x: jax.numpy.asarray(x, float) if eqx.is_inexact_array_like(x) else x, scene)
    (total, status), grad = _log_stiffness_and_gradient(scene, loads, weights)
    return (total, status[: GRADIENT_LOADS - pad]), grad


def params_of(scene):
    return jax.numpy.array([float(GETTERS[p](scene)) for p in PARAMS])


# Module-level jitted helpers, so that joints of one structure share a compile: run eagerly,
# each of the hundreds of operations in a joint's integrals would be compiled on its own.
@eqx.filter_jit
def total_loads(joint, log_a_l):
    """F_t*(a_l) at each ln a_l* (Eq. 30)."""
    return jax.vmap(joint.total_load)(log_a_l)


@eqx.filter_jit
def log_total_load_slopes(joint, log_a_l):
    """d ln F_t*/d ln a_l* at each ln a_l*."""
    return jax.vmap(jax.grad(lambda x: jax.numpy.log(joint.total_load(x))))(log_a_l)


def scipy_approach(scene, loads, F0, epsrel=1e-12):
    """δ(F) − δ(F0) = ∫_{F0}^{F} dF'/K(F') at each of `loads`, by scipy's adaptive quad in ln F, K from `solve`."""
    import numpy as np
    from scipy import integrate

    def one(F):
        value, _ = integrate.quad(
            lambda t: np.exp(t) / float(jc.solve(scene, np.exp(t)).stiffness),
            np.log(F0),
            np.log(F),
            epsrel=epsrel,
            epsabs=0.0,
            limit=400,
        )
        return value

    return np.array([one(float(F)) for F in np.atleast_1d(loads)])
