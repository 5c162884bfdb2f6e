"""Eager `jc.solve`: one compiled program per static configuration, load arrays padded to buckets."""

import os
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, make_scene

import jaxcontact as jc
from jaxcontact.core import _loadcontrol as loadcontrol
from jaxcontact.programs import _compiling as compiling
from jaxcontact.programs import _programs as programs
from jaxcontact.programs import program as store_program


def _compiled_lengths(scene, outputs):
    leaves, treedef = jax.tree_util.tree_flatten((scene, outputs))
    return programs.program(loadcontrol._solve, treedef).flat._cache_size()


def test_one_seven_thirty_and_two_hundred_loads_compile_the_solve_twice():
    # A configuration no other test uses, so that its program starts with an empty cache.
    scene = make_scene(**TABLE1, interaction="none", max_steps=63)
    outputs = jc.Outputs(regime_shares=False)
    jc.solve(scene, 22.0, outputs=outputs)
    for count in (7, 30, 200):
        jc.solve(scene, np.geomspace(1.0, 1e3, count), outputs=outputs)
    assert _compiled_lengths(scene, outputs) == 2


def test_a_single_load_padded_to_a_bucket_keeps_its_scalar_shape(table1_scene):
    solution = jc.solve(table1_scene, 22.0)
    assert solution.stiffness.shape == solution.status.shape == solution.modulus.shape == ()
    pair = jc.solve(table1_scene, np.array([22.0, 2200.0]))
    np.testing.assert_allclose(solution.stiffness, pair.stiffness[0], rtol=1e-14)


def test_an_eager_call_inside_a_callers_jit_gives_what_it_gives_outside(table1_scene):
    # Concrete scene and loads, yet inside a trace: the program must not ask for compile options there.
    loads = np.geomspace(2.2, 2200.0, 7)
    inside = jax.jit(lambda: jc.solve(table1_scene, loads).stiffness)()
    np.testing.assert_allclose(inside, jc.solve(table1_scene, loads).stiffness, rtol=1e-14)


def test_this_jaxlib_takes_the_fast_compile_option():
    assert compiling.compiler_options() == compiling.FAST_COMPILE


def test_a_fast_compile_program_also_runs_inside_a_callers_jit():
    program = compiling.FastCompile(lambda x: jnp.sin(x) * 2.0)
    x = jnp.linspace(0.0, 1.0, 5)
    np.testing.assert_allclose(jax.jit(lambda x: program(x) + 1.0)(x), jnp.sin(x) * 2.0 + 1.0, rtol=1e-15)


def test_buckets_are_octaves_to_128_loads_and_quarter_octaves_above():
    sizes = (1, 2, 32, 33, 128, 129, 160, 161, 200, 256, 257, 5000)
    assert [programs.bucket(n) for n in sizes] == [32, 32, 32, 64, 128, 160, 160, 192, 224, 256, 320, 5120]


@pytest.mark.parametrize("size", [1, 7, 200])
def test_edge_padding_is_numpys(size):
    values = np.geomspace(2.2, 2200.0, size)
    target = programs.bucket(size)
    np.testing.assert_array_equal(programs.edge_padded(values, target), np.pad(values, (0, target - size), mode="edge"))


def test_padded_loads_give_what_an_exact_compilation_gives(table1_scene):
    loads = jnp.geomspace(2.2, 2200.0, 200)
    eager = jc.solve(table1_scene, loads)
    exact = jax.jit(jc.solve)(table1_scene, loads)
    for name in ("a_l", "stiffness", "real_area", "load_share", "stiffness_share"):
        # Equal to round-off: XLA vectorises 224 and 200 lanes differently.
        np.testing.assert_allclose(getattr(eager, name), getattr(exact, name), rtol=1e-14, atol=1e-300, err_msg=name)


def test_padded_loads_keep_their_shape(table1_scene):
    loads = np.geomspace(2.2, 2200.0, 15).reshape(3, 5)
    solution = jc.solve(table1_scene, loads)
    assert solution.stiffness.shape == (3, 5)
    assert solution.load_share.shape == (3, 5, 4)
    assert solution.modulus.shape == (1, 1)
    np.testing.assert_array_equal(solution.load, loads)


def test_loads_a_bucket_long_keep_their_shape(table1_scene):
    loads = np.geomspace(2.2, 2200.0, 32)
    grid = jc.solve(table1_scene, loads.reshape(4, 8))
    np.testing.assert_array_equal(grid.stiffness, jc.solve(table1_scene, loads).stiffness.reshape(4, 8))


def test_the_padding_does_not_leak_into_a_flagged_batch(table1_scene):
    solution = jc.solve(table1_scene, np.array([2.2, 1e12, 22.0]))  # the middle load is beyond full contact
    assert solution.status.tolist() == [0, jc.Status.LOAD_OUT_OF_RANGE, 0]


def test_jax_load_arrays_checked_once_each_get_their_own_solution(table1_scene):
    a, b = np.geomspace(2.2, 2200.0, 7), np.geomspace(3.0, 3000.0, 7)
    expected = [jc.solve(table1_scene, x).stiffness for x in (a, a, b, b, a)]  # numpy: checked every call
    a, b = jnp.asarray(a), jnp.asarray(b)
    got = [jc.solve(table1_scene, x).stiffness for x in (a, a, b, b, a)]
    np.testing.assert_array_equal(np.stack(got), np.stack(expected))


def test_a_jax_load_array_is_padded_once_for_repeated_calls():
    # A caller's loop over scenes at one JAX array of loads: its padded copy is made once.
    loads = jnp.geomspace(2.2, 2200.0, 200)
    assert programs.padded(loads) is programs.padded(loads)


def test_a_bad_jax_load_array_is_refused_at_every_call(table1_scene):
    loads = jnp.array([22.0, -1.0])
    for _ in range(2):
        with pytest.raises(ValueError, match=r"loads\[1\] = -1.0 N"):
            jc.solve(table1_scene, loads)


def test_a_numpy_load_array_changed_in_place_is_checked_again(table1_scene):
    loads = np.array([22.0, 220.0])
    jc.solve(table1_scene, loads)
    loads[1] = np.nan
    with pytest.raises(ValueError, match=r"loads\[1\] = nan N"):
        jc.solve(table1_scene, loads)


def _counting(calls):
    def function(x, pair):
        calls.append(1)  # once per trace
        return jnp.sin(x) * pair[0] + pair[1], jnp.sum(x)

    return function


def _program_args():
    return np.linspace(0.0, 1.0, 5), (np.float64(2.0), np.arange(5, dtype=np.float64))


def test_an_exported_program_is_read_back_without_tracing(tmp_path):
    from jaxcontact.cli import _exported as exported

    x, pair = _program_args()
    calls = []
    with exported.exported_programs(tmp_path):
        first = store_program("demo", "static", _counting(calls), (x, pair))(x, pair)
        assert len(calls) == 1
        assert len(list(tmp_path.glob("demo-*.jaxexport"))) == 1
        again = store_program("demo", "static", _counting(calls), (x, pair))(x, pair)
    assert len(calls) == 1  # read from disk: not traced again
    expected = jax.jit(_counting([]))(x, pair)
    for got in (first, again):
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_array_equal(got[1], expected[1])


def test_another_static_description_or_shape_is_another_exported_program(tmp_path):
    from jaxcontact.cli import _exported as exported

    x, pair = _program_args()
    with exported.exported_programs(tmp_path):
        store_program("demo", "static", _counting([]), (x, pair))
        store_program("demo", "other", _counting([]), (x, pair))
        store_program("demo", "static", _counting([]), (x[:4], (pair[0], pair[1][:4])))
    assert len(list(tmp_path.glob("demo-*.jaxexport"))) == 3


def test_an_unreadable_exported_program_is_traced_instead(tmp_path):
    from jaxcontact.cli import _exported as exported

    x, pair = _program_args()
    with exported.exported_programs(tmp_path):
        store_program("demo", "static", _counting([]), (x, pair))
        (path,) = tmp_path.glob("demo-*.jaxexport")
        path.write_bytes(b"not an exported program")
        calls = []
        got = store_program("demo", "static", _counting(calls), (x, pair))(x, pair)
    assert len(calls) == 1
    np.testing.assert_array_equal(got[0], jax.jit(_counting([]))(x, pair)[0])


def test_without_a_directory_nothing_is_written(tmp_path, monkeypatch):

    monkeypatch.chdir(tmp_path)
    x, pair = _program_args()
    store_program("demo", "static", _counting([]), (x, pair))(x, pair)
    assert not list(tmp_path.rglob("*"))


def test_a_changed_source_file_of_a_closed_over_class_is_another_exported_program(tmp_path, monkeypatch):
    """A model defined outside the package: editing its file must not read the old program."""
    import importlib

    from jaxcontact.cli import _exported as exported

    source = tmp_path / "outside_model.py"
    source.write_text("import equinox as eqx\n\n\nclass Outside(eqx.Module):\n    scale: float = 2.0\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("outside_model")
    treedef = jax.tree_util.tree_structure(module.Outside())
    x, pair = _program_args()
    store = tmp_path / "store"
    with exported.exported_programs(store):
        store_program("demo", "static", _counting([]), (x, pair), closed_over=(treedef,))
        source.write_text(source.read_text() + "# edited\n")
        store_program("demo", "static", _counting([]), (x, pair), closed_over=(treedef,))
    assert len(list(store.glob("demo-*.jaxexport"))) == 2


def test_a_solve_kept_on_disk_is_read_back_untraced_with_the_same_solution(tmp_path):
    from jaxcontact.cli import _exported as exported

    # A configuration no other test uses, so that its program is not already traced here.
    scene = make_scene(**TABLE1, interaction="series", quadrature_nodes=19)
    loads = np.geomspace(2.2, 2200.0, 40)
    with exported.exported_programs(tmp_path):
        first = jc.solve(scene, loads)
        programs.program.cache_clear()
        again = jc.solve(scene, loads)
    assert _compiled_lengths(scene, jc.Outputs()) == 0  # never traced in its place
    assert jax.tree_util.tree_structure(again) == jax.tree_util.tree_structure(first)
    for name in ("a_l", "stiffness", "real_area", "status", "load_share", "modulus"):
        np.testing.assert_array_equal(getattr(again, name), getattr(first, name), err_msg=name)


def test_a_later_process_reads_the_solves_executable_and_compiles_nothing(tmp_path):
    # In fresh processes without JAX's compilation cache: an executable that JAX read from that
    # cache is not kept (it does not survive serialisation), and the suite's cache outlives a run.
    code = f"""
import logging, jax, numpy as np
jax.config.update("jax_enable_x64", True)
jax.config.update("jax_log_compiles", True)
import jaxcontact as jc
from jaxcontact.cli import _exported as exported
compiled = []
class Names(logging.Handler):
    def emit(self, record):
        if record.getMessage().startswith("Finished XLA compilation of"):
            compiled.append(record.getMessage().split()[4])
logging.getLogger("jax._src.dispatch").addHandler(Names())
with exported.exported_programs({str(tmp_path)!r}):
    stiffness = jc.solve(jc.table1_scene(interaction="series"), np.geomspace(2.2, 2200.0, 40)).stiffness
print(",".join(compiled), repr(float(stiffness[7])))
"""
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)]
    runs.append(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env))
    (first_compiled, first_value), (later_compiled, later_value) = (run.stdout.split() for run in runs)
    assert len(list(tmp_path.glob("solve-*.jaxexec"))) == 1
    assert not list(tmp_path.glob("solve-*.jaxexport"))  # kept instead of the exported program, not beside it
    assert "jit(flat)" in first_compiled.split(",")  # the solve, compiled once, from the function itself
    assert not {"jit(flat)", "jit(call)"} & set(later_compiled.split(","))  # read back: only the small cut is compiled
    assert later_value == first_value


def test_a_kept_executable_that_fails_is_deleted_and_the_exported_program_used(tmp_path):
    from jaxcontact.cli import _exported as exported

    def broken(*args):
        raise RuntimeError("Function add_divide_fusion not found")

    path = tmp_path / "solve-x-y.jaxexec"
    path.write_bytes(b"kept")
    kept = exported._Kept(broken, path, fallback=lambda: lambda x: x + 1.0)
    assert kept(1.0) == 2.0
    assert not path.exists()


def test_the_command_lines_short_compile_solve_gives_the_default_compilations_numbers(tmp_path):
    # The suite compiles everything with the classic emitters (conftest): the two compilers meet
    # only in a process without that flag.
    code = f"""
import jax, numpy as np
jax.config.update("jax_enable_x64", True)
import jaxcontact as jc
from jaxcontact.cli import _exported as exported
scene, loads = jc.table1_scene(), np.geomspace(2.2, 22000.0, 41)  # the default scene's F* 1e-7 to 1e-3
default = jc.solve(scene, loads)
with exported.exported_programs({str(tmp_path)!r}):
    short = jc.solve(scene, loads)
ok = np.asarray(default.status) == 0
print(int(ok.sum()), np.array_equal(default.status, short.status))
print(max(float(np.max(np.abs(getattr(short, n)[ok] / getattr(default, n)[ok] - 1))) for n in ("a_l", "stiffness")))
"""
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    counts, worst = out.stdout.split("\n")[:2]
    assert counts == "40 True"  # the highest load, F* = 1e-3, is past the "paper" interaction's breakdown
    assert float(worst) < 1e-13


@pytest.mark.parametrize(
    "options, shares",
    [
        (dict(), True),
        (dict(), False),
        (dict(model="jzz2010"), True),
        (dict(model="gw"), True),
        (dict(model="persson"), True),
    ],
    ids=["xia2024", "no-shares", "jzz2010", "gw", "persson"],
)
def test_the_solution_tree_is_known_without_tracing(options, shares):
    scene, outputs = make_scene(**TABLE1, **options), jc.Outputs(regime_shares=shares)
    leaves, treedef = jax.tree_util.tree_flatten((scene, outputs))
    traced = jax.tree_util.tree_structure(
        jax.eval_shape(lambda s, F: jc.solve(s, F, outputs=outputs), scene, jnp.ones(3))
    )
    assert loadcontrol._solution_tree(treedef)(leaves) == traced


class _Installed:
    """A distribution as importlib.metadata gives it: a version, and how it was installed."""

    def __init__(self, version, direct_url):
        self.version, self.direct_url = version, direct_url

    def read_text(self, name):
        return self.direct_url if name == "direct_url.json" else None


def _identity(monkeypatch, distribution):
    from jaxcontact.cli import _exported as exported

    monkeypatch.setattr(exported.importlib.metadata, "distribution", lambda name: distribution)
    jc.clear_caches()
    try:
        return exported.installed()
    finally:
        monkeypatch.undo()
        jc.clear_caches()


def test_kept_programs_of_an_installed_release_are_keyed_on_its_version(monkeypatch):
    assert _identity(monkeypatch, _Installed("9.9.9", None)) == "jaxcontact 9.9.9"


EDITABLE = '{"url": "file:///src", "dir_info": {"editable": true}}'


def test_kept_programs_of_an_editable_install_are_keyed_on_a_digest_of_its_source(monkeypatch):
    assert len(_identity(monkeypatch, _Installed("9.9.9", EDITABLE))) == 64  # sha256, hex


def test_an_editable_installs_key_changes_with_its_version_too(monkeypatch):
    assert _identity(monkeypatch, _Installed("9.9.9", EDITABLE)) != _identity(
        monkeypatch, _Installed("9.9.8", EDITABLE)
    )


def test_a_stored_solve_is_kept_per_length_of_a_models_table(tmp_path):
    # The command line's store: two scenes of one structure whose spectra differ in length.
    from jaxcontact.cli import _exported as exported

    q = np.geomspace(1e5, 1e7, 40)

    def stiffness(points):
        spectrum = jc.MeasuredSpectrum(q[:points], 1e-30 * (q[:points] / 1e5) ** -3.2)
        scene = make_scene(**dict(TABLE1, model=jc.Persson(spectrum=spectrum)))
        return float(jc.solve(scene, 1.0).stiffness)

    expected = stiffness(20)
    with exported.exported_programs(tmp_path):
        stiffness(40)
        assert stiffness(20) == expected
