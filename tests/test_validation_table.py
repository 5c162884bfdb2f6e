"""The committed validation table (data/validation_bem.csv, docs/validation.md) is what its command
computes: regenerated here on a smaller grid with one realisation."""

import csv
import re

import numpy as np
import pytest
from helpers import ROOT

from jaxcontact.cli._compare_table import compare_spec
from jaxcontact.studies._compare import COMPARED, column_key, validation_rows

pytest.importorskip("ContactMechanics")
TABLE = ROOT / "data" / "validation_bem.csv"
GRID_TOLERANCE = 0.03  # K at 256² against 512² on the same surfaces (tests/test_bem.py)


def committed():
    lines = TABLE.read_text().splitlines()
    command = lines[0]
    return command, list(csv.DictReader(line for line in lines if not line.startswith("#")))


@pytest.fixture(scope="module")
def regenerated():
    class Args:
        scene = None

    return validation_rows(compare_spec(Args).scene, grid=256, realisations=1, convergence=False)


def test_the_table_names_its_command():
    command, _ = committed()
    assert re.fullmatch(r"# jaxcontact compare --validation --grid 512 --realisations 3 --seed 0", command)


def test_the_loads_are_the_commands(regenerated):
    _, rows = committed()
    np.testing.assert_allclose([r["F_N"] for r in regenerated], [float(r["F_N"]) for r in rows], rtol=1e-10)


def test_the_bem_stiffness_lies_within_the_committed_spread(regenerated):
    _, rows = committed()
    K = np.array([r["K_bem_mean_N_per_m"] for r in regenerated])
    low = np.array([float(r["K_bem_low_N_per_m"]) for r in rows]) * (1 - GRID_TOLERANCE)
    high = np.array([float(r["K_bem_high_N_per_m"]) for r in rows]) * (1 + GRID_TOLERANCE)
    assert np.all((low <= K) & (K <= high)), np.c_[low, K, high]


@pytest.mark.parametrize("label", list(COMPARED))
def test_each_models_committed_stiffness_is_recomputed(regenerated, label):
    _, rows = committed()
    key = column_key(label)
    np.testing.assert_allclose(
        [r[f"K_{key}_N_per_m"] for r in regenerated], [float(r[f"K_{key}_N_per_m"]) for r in rows], rtol=1e-9
    )
