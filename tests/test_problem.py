"""`fitting.Problem`: the one fitting problem that `fit`, `fit_batch` and `sample` drive, and its JAX
residual function (`Problem.misfit`), against the host fit's own residuals and central differences."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1_WITHOUT_INTERACTION as TRUTH
from helpers import WRONG_START as START
from helpers import make_scene

from jaxcontact import InputError, fitting
from jaxcontact.fitting._synthetic import synthetic_curve


@pytest.fixture(scope="module")
def fitted():
    """The seed model's curve fitted by `fit` (its loads padded for its compiled program), and the
    problem of that curve with the fit's optimum in optimiser coordinates. Made here, not when the
    module is imported: both workers import every test module."""
    loads, stiffness = synthetic_curve(make_scene(**TRUTH), np.geomspace(1e-10, 1e-4, 12), noise=0.05, seed=4)
    result = fitting.fit(loads, stiffness, make_scene(**START), n_starts=4)
    problem = fitting.Problem.of(loads, stiffness, make_scene(**START))
    u = np.array([p.u_from_stat(p.to_stat(result.values[p.name])) for p in problem.params])
    return result, problem, jnp.asarray(u)


def test_the_misfits_loss_at_the_optimum_is_the_fits_loss(fitted):
    result, problem, u = fitted
    assert float(problem.misfit().loss(u)) == pytest.approx(result.loss, rel=1e-9)


def test_the_misfits_gradient_vanishes_at_the_fits_optimum(fitted):
    """Relative to the gradient one standard error away (the loss's curvature scale)."""
    _, problem, u = fitted
    grad = jax.grad(problem.misfit().loss)
    away = jnp.abs(grad(u + jnp.array([0.05, 0.0])))
    assert float(jnp.max(jnp.abs(grad(u)))) < 1e-5 * float(jnp.max(away))


@pytest.mark.parametrize("i", [0, 1])
def test_the_misfits_gradient_is_central_differences(fitted, i):
    """`jax.grad` of the loss (its forward-mode gradient) against central differences of the loss."""
    _, problem, u = fitted
    loss = eqx.filter_jit(problem.misfit().loss)
    point = u + jnp.array([0.3, -0.2])
    h = 1e-5 * jnp.zeros(2).at[i].set(1.0)
    fd = (loss(point + h) - loss(point - h)) / (2e-5)
    np.testing.assert_allclose(jax.grad(problem.misfit().loss)(point)[i], fd, rtol=1e-6)


def test_its_starts_begin_at_the_scenes_own_values(fitted):
    _, problem, _ = fitted
    own = [p.from_stat(p.stat_from_u(x)) for p, x in zip(problem.params, problem.starts(4, 0)[0])]
    np.testing.assert_allclose(own, [START["D"], START["G"]], rtol=1e-12)


def test_a_curve_of_two_distinct_loads_cannot_determine_two_parameters():
    with pytest.raises(InputError, match="2 distinct values among 4 points cannot determine 2 parameters"):
        fitting.Problem.of([1.0, 1.0, 2.0, 2.0], [1e8, 1e8, 2e8, 2e8], make_scene(**START))
