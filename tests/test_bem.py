"""The boundary-element reference (docs/model.md §10) against Hertz, its own grid, and the models."""

import math

import numpy as np
import pytest
from helpers import BEM_L as L
from helpers import BEM_SETTING, make_scene

import jaxcontact as jc
from jaxcontact import bem

SurfaceTopography = pytest.importorskip("SurfaceTopography")
pytest.importorskip("ContactMechanics")

E = BEM_SETTING["E"]
UNIT_LOAD = E * L * L


def paraboloid(n=256, radius=1.0, size=1.0):
    x = (np.arange(n) + 0.5) * size / n - size / 2
    return SurfaceTopography.Topography(
        -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius), (size, size), periodic=False
    )


@pytest.fixture(scope="module")
def hertz():
    a = 0.1  # contact radius: 25.6 grid spacings
    F = 4 * a**3 / 3  # Hertz, E = R = 1
    return a, bem.bem_stiffness(paraboloid(), 1.0, [F], substrate=bem.Free())


def test_hertz_contact_radius(hertz):
    a, result = hertz
    np.testing.assert_allclose(math.sqrt(result.contact_fraction[0] / math.pi), a, rtol=0.02)


def test_hertz_stiffness_is_2Ea(hertz):
    a, result = hertz
    np.testing.assert_allclose(result.stiffness[0], 2 * a, rtol=0.02)


@pytest.mark.parametrize("coarse", [8, 9])
def test_coarsening_keeps_a_band_limited_surface(coarse):
    """A surface of the grid's lowest wavevectors, sampled on 2n points, coarsened to n (even and odd)."""

    def heights(n):
        x = np.arange(n) / n
        return (
            np.cos(2 * np.pi * x)[:, None]
            + np.sin(2 * np.pi * 3 * x)[None, :]
            + 0.5 * np.cos(2 * np.pi * (x[:, None] - 2 * x[None, :]))
        )

    fine = SurfaceTopography.Topography(heights(2 * coarse), (1.0, 1.0), periodic=True)
    np.testing.assert_allclose(bem.coarsened(fine).heights(), heights(coarse), atol=1e-12)


def test_a_non_periodic_map_needs_an_explicit_substrate():
    with pytest.raises(ValueError, match=r"not periodic: choose substrate = bem.Free\(\)"):
        bem.bem_stiffness(paraboloid(32), 1.0, [1e-3])


def test_a_grid_too_coarse_for_l_min_is_refused():
    with pytest.raises(ValueError, match=r"grid = 128 is too coarse for l_min .* \(grid >= 256"):
        bem.realisation(1.5, 1e-12, L / 64, L, 128, 0)


def test_the_iteration_cap_gives_not_converged():
    surface = bem.realisation(1.5, 1e-12, L / 16, L, 64, 0)
    result = bem.bem_stiffness(surface, E, [1e-4 * UNIT_LOAD], settings=bem.BEMSettings(max_iterations=2))
    assert result.status[0] == jc.Status.NOT_CONVERGED
    assert np.isnan(result.stiffness[0])


def test_a_solve_leaves_nothing_in_contactmechanicss_default_logger():
    # Its default logger (one object for the process) would keep a line per iteration of every solve.
    from ContactMechanics.Tools.Logger import quiet

    before = len(quiet.buffer)
    bem.bem_stiffness(bem.realisation(1.5, 1e-12, L / 8, L, 32, 0), E, [1e-3 * UNIT_LOAD])
    assert len(quiet.buffer) == before


def test_full_contact_is_out_of_range():
    surface = bem.realisation(1.5, 1e-12, L / 16, L, 64, 0)
    result = bem.bem_stiffness(surface, E, [1e-1 * UNIT_LOAD])
    assert result.status[0] == jc.Status.LOAD_OUT_OF_RANGE


def test_results_are_read_back_from_the_cache(tmp_path, monkeypatch):
    surface = bem.realisation(1.5, 1e-12, L / 16, L, 64, 0)
    cache = bem.ResultCache(tmp_path)
    first = bem.bem_stiffness(surface, E, [1e-4 * UNIT_LOAD], cache=cache)

    def no_solve(*args):
        raise AssertionError("solved again")

    monkeypatch.setattr(bem._solver, "_one_load", no_solve)
    again = bem.bem_stiffness(surface, E, [1e-4 * UNIT_LOAD], cache=cache)
    np.testing.assert_array_equal(again.stiffness, first.stiffness)


@pytest.fixture(scope="module")
def d15_reference():
    """Two realisations of docs/model.md §10's D = 1.5 surface on 256², at contact fractions ~0.5–20 %."""
    scene = make_scene(**BEM_SETTING)
    return bem.reference_curves(scene, np.array([2e-5, 1e-4, 5e-4]) * UNIT_LOAD, grid=256, realisations=2)


def test_reference_loads_span_the_contact_fractions(d15_reference):
    fractions = d15_reference.contact_fraction
    assert fractions[0] > 0.005 and fractions[-1] < 0.2


def test_grid_convergence_half_grid_within_3_percent(d15_reference):
    """K on the same surfaces at 128² against 256² (l_min = 4 and 2 grid spacings)."""
    assert np.all(np.abs(d15_reference.grid_change) < 0.03)


def test_persson_is_within_35_percent_of_the_bem(d15_reference):
    K = np.asarray(jc.solve(make_scene(**BEM_SETTING, model="persson"), d15_reference.loads).stiffness)
    np.testing.assert_allclose(K / d15_reference.mean, 1.0, atol=0.35)
