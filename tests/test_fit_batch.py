"""Many curves at once (optax L-BFGS, vmapped): the same optima, intervals and warnings as fitting
each curve with `fitting.fit`."""

import numpy as np
import pytest
from helpers import TABLE1_WITHOUT_INTERACTION as TRUTH
from helpers import WRONG_START as START
from helpers import make_scene

import fitting
from fitting._synthetic import synthetic_curve

# Without interaction (TRUTH): the batch program compiles in a quarter of the time, and the fit is the same fit.
F_STAR = np.geomspace(1e-10, 1e-4, 20)


@pytest.fixture(scope="module")
def curves():
    scene = make_scene(**TRUTH)
    loads, K = zip(*(synthetic_curve(scene, F_STAR, noise=0.05, seed=300 + s) for s in range(6)))
    return np.array(loads), np.array(K)


@pytest.fixture(scope="module")
def batch(curves):
    return fitting.fit_batch(*curves, make_scene(**START), n_starts=4)


@pytest.fixture(scope="module")
def one_by_one(curves):
    return [fitting.fit(loads, K, make_scene(**START), n_starts=4) for loads, K in zip(*curves)]


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_batch_finds_each_curves_optimum(batch, one_by_one, name):
    looped = np.array([r.values[name] for r in one_by_one])
    assert np.allclose(batch.values[name], looped, rtol=1e-5, atol=0)


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_batch_gives_each_curves_standard_error(batch, one_by_one, name):
    looped = np.array([r.stderr[name] for r in one_by_one])
    assert np.allclose(batch.stderr[name], looped, rtol=1e-3, atol=0)


def test_every_curve_converges(batch):
    assert batch.success.all()


def test_a_second_batch_of_the_same_shape_compiles_nothing(curves, batch):
    again = fitting.fit_batch(curves[0], curves[1] * 1.01, make_scene(**START), n_starts=4)
    assert again.compile_time < 0.1 * batch.compile_time


def test_the_intervals_cover_the_truth_in_most_curves(batch):
    lo, hi = batch.ci95["D"].T
    assert np.sum((lo < TRUTH["D"]) & (TRUTH["D"] < hi)) >= 5


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(loads=np.ones((2, 3)), stiffness=np.ones((3, 3))), r"loads \(2, 3\) and stiffness \(3, 3\) differ"),
        (dict(loads=np.ones((2, 2)), stiffness=np.ones((2, 2))), "2 points per curve cannot determine 2"),
        (dict(loads=-np.ones((2, 5)), stiffness=np.ones((2, 5))), "loads must be positive"),
    ],
)
def test_bad_batches_are_refused_by_name(kw, message):
    with pytest.raises(ValueError, match=message):
        fitting.fit_batch(kw["loads"], kw["stiffness"], make_scene(**START))
