"""`jc.solve_path`, the joint along a load path: an elastic model against the closed form of Hertz
summits of uniform heights, the capped boundary-element model
against `bem.solve_path` of its own surfaces in SI units, the command, and the models refused."""

import csv
import math

import numpy as np
import pytest
from helpers import TABLE1

import jaxcontact as jc
from jaxcontact import bem
from jaxcontact.cli import main

B = jc.Branch
E, AREA, R, ETA, DELTA = 1e11, 1e-4, 1e-4, 1e9, 2e-6  # Pa, m², m, summits per m², m
PATH = np.array([0.3, 3.0, 1.0, 0.3, 3.0, 30.0])  # N: load, unload, reload, load further


def uniform_summits():
    heights = np.linspace(0.0, DELTA, 201)
    surface = jc.Surface(D=TABLE1["D"], G=TABLE1["G"], l_min=TABLE1["l_min"])  # not used by the model
    model = jc.MeasuredAsperities(R, ETA, heights, np.ones_like(heights))
    return jc.Scene(surface, jc.Material(E=E, nu=0.3, H=3e9), AREA, model=model)


def interference(F):
    """Summit heights uniform on [0, Δ]: F = A η (4/3) E √R s^{5/2} / (5Δ/2), s the flat's depth into them."""
    return (np.asarray(F) * 2.5 * DELTA / (AREA * ETA * 4 / 3 * E * math.sqrt(R))) ** 0.4


@pytest.fixture(scope="module")
def summits():
    return uniform_summits()


@pytest.fixture(scope="module")
def elastic_path(summits):
    return jc.solve_path(summits, PATH)


def test_each_point_is_on_the_branch_its_load_reaches(elastic_path):
    expected = [B.LOADING, B.LOADING, B.UNLOADING, B.UNLOADING, B.RELOADING, B.LOADING]
    assert np.asarray(elastic_path.branch).tolist() == expected


def test_an_elastic_path_has_the_closed_form_approach(elastic_path):
    # Every branch retraces the loading curve: the approach is s(F) − s(F₀) whatever came before.
    expected = interference(PATH) - interference(PATH[0])
    np.testing.assert_allclose(np.asarray(elastic_path.approach), expected, rtol=1e-9, atol=1e-18)


def test_an_elastic_path_has_the_closed_form_stiffness(elastic_path):
    s = interference(PATH)
    expected = AREA * ETA * 2 * E * math.sqrt(R) * s**1.5 / (1.5 * DELTA)
    np.testing.assert_allclose(np.asarray(elastic_path.unloading_stiffness), expected, rtol=1e-10)


L = 100e-6
BEM_PATH = np.array([1e-3, 2e-3, 1.6e-3, 1e-3, 2e-3, 3e-3]) * 210e9 * L * L  # F* 1e-3 … 3e-3


def bem_scene(plastic):
    surface = jc.Surface(D=1.5, G=1e-10, l_min=L / 8)
    model = jc.BEM(grid=32, realisations=2, plastic=plastic)
    return jc.Scene(surface, jc.Material(E=210e9, nu=0.3, H=0.015 * 210e9), L * L, model=model)


@pytest.fixture(scope="module")
def capped():
    scene = bem_scene(True)
    own = [bem.solve_path(h, L, 210e9, BEM_PATH, hardness=0.015 * 210e9) for h in scene.model.heights(scene)]
    return jc.solve_path(scene, BEM_PATH), own


def test_the_capped_bem_models_path_is_the_mean_of_its_surfaces_paths(capped):
    path, own = capped
    expected = np.mean([p.unloading_stiffness for p in own], axis=0)
    np.testing.assert_allclose(np.asarray(path.unloading_stiffness), expected, rtol=1e-9)


def test_the_capped_bem_models_approach_is_the_mean_of_its_surfaces_approaches(capped):
    path, own = capped
    expected = np.mean([p.approach for p in own], axis=0)
    np.testing.assert_allclose(np.asarray(path.approach), expected, rtol=1e-9, atol=1e-9 * expected.max())


def test_the_capped_bem_models_residual_approach_is_its_surfaces_mean(capped):
    path, own = capped
    expected = np.mean([float(p.residual_approach) for p in own])
    assert expected > 0
    np.testing.assert_allclose(float(path.residual_approach), expected, rtol=1e-9)


def test_the_capped_bem_model_unloads_stiffer_than_it_loads(capped):
    path, _ = capped
    assert float(path.unloading_stiffness[1]) > 1.05 * float(path.stiffness[1])


def test_the_capped_bem_model_reloads_to_its_old_maximum_elastically(capped):
    # Back at the old maximum (a kink): the state left there, with its elastic tangent.
    path, _ = capped
    np.testing.assert_allclose(float(path.stiffness[4]), float(path.unloading_stiffness[1]), rtol=1e-6)


def test_the_capped_bem_models_dynamic_stiffness_is_its_paths_unloading_tangent_at_each_top(capped):
    # Preloads in any order, each reached by loading through the smaller ones: the path's points
    # reached by loading (1e-3, 2e-3, and 3e-3 after an elastic unload and reload), whose surfaces
    # the cycle between them leaves as they were.
    path, _ = capped
    dynamic = jc.dynamic_stiffness(bem_scene(True), BEM_PATH[[5, 0, 1]]).stiffness
    np.testing.assert_allclose(np.asarray(dynamic), np.asarray(path.unloading_stiffness)[[5, 0, 1]], rtol=1e-6)


def test_a_flowing_model_without_a_path_law_is_refused():
    with pytest.raises(ValueError, match="model = 'xia2024' has no load-path law"):
        jc.solve_path(jc.table1_scene(), PATH)


@pytest.mark.parametrize("path", [PATH[None, :], np.array([1.0, float("nan")]), np.array([1.0, -1.0])])
def test_a_bad_path_is_refused_by_name(summits, path):
    with pytest.raises(ValueError, match="path|loads"):
        jc.solve_path(summits, path)


def test_the_commands_path_csv_is_the_librarys_path(summits, elastic_path, tmp_path):
    # `jaxcontact cycle --path` writes what `run_path` writes; on the summits' scene its programs are
    # the ones compiled above.
    from jaxcontact.cli._path_command import run_path
    from jaxcontact.cli._scenefile import SceneFile

    spec = SceneFile(title="summits", scene=summits, loads=PATH, source="test")
    run_path(spec, PATH, tmp_path)
    with open(tmp_path / "path.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    approach = [float(row["approach_m"]) for row in rows]
    np.testing.assert_allclose(approach, np.asarray(elastic_path.approach), rtol=1e-12, atol=1e-20)


def test_the_command_refuses_a_model_without_a_path_law(tmp_path, capsys):
    assert main(["cycle", "--path", "1", "2", "--out", str(tmp_path)]) == 2
    assert "model = 'xia2024' has no load-path law" in capsys.readouterr().err
