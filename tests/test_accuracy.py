"""The accuracy study and its high-precision reference."""

import csv

import numpy as np
from helpers import CHECKPOINTS, TABLE1, make_scene

from jaxcontact.studies import _reference as reference
from jaxcontact.studies._accuracy import _dominates, study


def test_mpmath_reference_matches_the_conformance_vectors():
    rows = [
        r
        for r in csv.DictReader(open(CHECKPOINTS))
        if r["model"] == "xia2024" and r["distribution"] == "mb" and r["status"] == "ok"
    ][::4]
    assert len(rows) >= 8
    for r in rows:
        K, a_l = reference.stiffness(*(float(r[k]) for k in "D G E nu H area l_min load_N".split()), r["interaction"])
        np.testing.assert_allclose([K, a_l], [float(r["stiffness_N_per_m"]), float(r["a_l_m2"])], rtol=1e-8)


def test_quick_study_orders_the_node_counts():
    result = study(make_scene(**TABLE1), quick=True)
    errors = {r["knob"]: r["max_rel_error"] for r in result["rows"]}
    four, sixteen, thirty_two = (errors[f"Gauss–Legendre, {n} nodes"] for n in (4, 16, 32))
    series = errors["power series of the pole term (no nodes)"]
    assert four > 1e-4 > sixteen > thirty_two  # near breakdown 4 nodes are visibly wrong
    assert sixteen < 1e-11
    # Round-off amplified by K's conditioning 0.9998 of the way to breakdown.
    assert thirty_two < 1e-12
    assert series < 1e-12
    assert [r["default"] for r in result["rows"]] == [True, False, False, False]


def test_pareto_dominance_ignores_round_off():
    fast = dict(max_rel_error=3e-15, ms_per_1000_loads=1.0)
    slow = dict(max_rel_error=2e-15, ms_per_1000_loads=2.0)
    assert _dominates(fast, slow)
    assert not _dominates(slow, fast)
    assert not _dominates(fast, dict(fast))
