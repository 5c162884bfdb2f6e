"""The boundary-element cache: an entry is served only when it describes what was asked and is intact."""

import json
import shutil

import numpy as np
import pytest
from helpers import BEM_L as L
from helpers import BEM_SETTING

from jaxcontact import bem

pytest.importorskip("ContactMechanics")

E = BEM_SETTING["E"]
LOADS = np.array([2e-4, 6e-4]) * E * L * L


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    """Two loads on a small surface, solved once into a cache; each test works on a copy of it."""
    directory = tmp_path_factory.mktemp("cache")
    surface = bem.realisation(1.5, 1e-12, L / 16, L, 64, 0)
    result = bem.bem_stiffness(surface, E, LOADS, cache=bem.ResultCache(directory))
    return surface, result, directory


@pytest.fixture
def cache(solved, tmp_path):
    shutil.copytree(solved[2], tmp_path / "cache")
    return bem.ResultCache(tmp_path / "cache")


def entry_path(cache, surface, load):
    settings = bem.BEMSettings()
    described = cache.surface_key(surface.heights(), surface.physical_sizes, E, bem.Periodic(), settings)
    return cache.path(cache.key(described, load))


def solve_again(solved, cache):
    surface, first, _ = solved
    with pytest.warns(bem.CacheWarning) as caught:
        again = bem.bem_stiffness(surface, E, LOADS, cache=cache)
    return first, again, [str(w.message) for w in caught]


def test_an_intact_entry_is_served_without_a_warning(solved, cache, recwarn):
    again = bem.bem_stiffness(solved[0], E, LOADS, cache=cache)
    np.testing.assert_array_equal(again.stiffness, solved[1].stiffness)
    assert not [w for w in recwarn if issubclass(w.category, bem.CacheWarning)]


def test_an_edited_number_is_recomputed_not_served(solved, cache):
    path = entry_path(cache, solved[0], LOADS[0])
    entry = json.loads(path.read_text())
    entry["row"]["stiffness"] *= 3.0
    path.write_text(json.dumps(entry))
    first, again, messages = solve_again(solved, cache)
    np.testing.assert_array_equal(again.stiffness, first.stiffness)
    assert messages == [f"cache entry {path} was invalid (its checksum does not match its content); recomputed"]


def test_an_entry_copied_over_another_is_recomputed(solved, cache):
    low, high = (entry_path(cache, solved[0], load) for load in LOADS)
    shutil.copyfile(low, high)
    first, again, messages = solve_again(solved, cache)
    np.testing.assert_array_equal(again.stiffness, first.stiffness)
    assert messages == [f"cache entry {high} was invalid (it describes another surface, load or setting); recomputed"]


def _rewrite_row(path, **row):
    """An entry with a consistent checksum but the given fields in its result."""
    from jaxcontact.bem._cache import _digest

    entry = json.loads(path.read_text())
    entry["row"].update(row)
    entry["checksum"] = _digest({"describes": entry["describes"], "row": entry["row"]})
    path.write_text(json.dumps(entry))


@pytest.mark.parametrize(
    "change, why",
    [
        (dict(stiffness=float("nan")), "its status is ok but its stiffness"),
        (dict(stiffness="1e6"), "its stiffness is '1e6', not a number"),
        (dict(status=[0]), "its status is [0], not an integer"),
        (dict(fraction=1.5), "its status is ok but its stiffness, offset or contact fraction is not valid"),
    ],
)
def test_a_well_formed_entry_with_a_bad_result_is_recomputed(solved, cache, change, why):
    path = entry_path(cache, solved[0], LOADS[1])
    _rewrite_row(path, **change)
    first, again, messages = solve_again(solved, cache)
    np.testing.assert_array_equal(again.stiffness, first.stiffness)
    assert len(messages) == 1 and why in messages[0]


@pytest.mark.parametrize("text", ["{}", "[1, 2]", '"a string"', "not json at all", ""])
def test_an_entry_that_is_not_an_entry_is_recomputed(solved, cache, text):
    path = entry_path(cache, solved[0], LOADS[0])
    path.write_text(text)
    first, again, messages = solve_again(solved, cache)
    np.testing.assert_array_equal(again.stiffness, first.stiffness)
    assert len(messages) == 1 and messages[0].startswith(f"cache entry {path} was invalid (")


def test_a_recomputed_entry_is_written_back_valid(solved, cache):
    path = entry_path(cache, solved[0], LOADS[0])
    path.write_text("{}")
    solve_again(solved, cache)
    row, why = cache.lookup(cache.key(json.loads(path.read_text())["describes"], LOADS[0]))
    assert why is None and row["stiffness"] == solved[1].stiffness[0]


WRITER = """
import sys
from jaxcontact.bem import ResultCache
cache = ResultCache(sys.argv[1])
keys = [cache.key({"surface": k}, 1.0) for k in range(3)]
row = dict(stiffness=1e6, offset=1e-8, fraction=0.1, status=0, iterations=5)
failures = 0
for _ in range(300):
    for key in keys:
        try:
            cache.put(key, row)
            failures += cache.lookup(key)[0] != row
        except Exception as exc:
            failures += 1
            print(repr(exc), file=sys.stderr)
print(failures)
"""


def test_concurrent_writers_of_the_same_keys_never_fail(tmp_path):
    """Two processes writing the same three keys 300 times each: no error, every read back valid."""
    import subprocess
    import sys

    writers = [
        subprocess.Popen([sys.executable, "-c", WRITER, str(tmp_path)], stdout=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    outputs = [w.communicate(timeout=300)[0] for w in writers]
    assert [w.returncode for w in writers] == [0, 0]
    assert [int(o) for o in outputs] == [0, 0]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        f"{bem.ResultCache.key({'surface': k}, 1.0).name}.json" for k in range(3)
    )
