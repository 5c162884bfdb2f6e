"""The 200-load curve and the fit of `jaxcontact bench` timed as a user's process runs them: JAX's default settings.

The command line runs compiled calls synchronously (`cli._process.command_settings`), and JAX reads
that setting only when it creates its CPU client, so the bench process cannot time the calls as a
notebook or a script makes them. This module times `curve` (scipy and every jaxcontact call,
interleaved, in the same run), and a user's first fit and the fits after it, in a fresh Python
process that switches float64 on and nothing else: asynchronous dispatch, no persistent
compilation cache, no stored programs.

Run as `python -m jaxcontact.studies._bench_user`: a pickled `(what, arguments)` on stdin, the
results as JSON on stdout.
"""

from __future__ import annotations

import json
import pickle
import subprocess
import sys
import time

import numpy as np

from ..core import Scene


def _in_a_fresh_process(what: str, arguments: tuple) -> dict:
    # The environment is inherited: JAX_ and XLA_ variables are the user's settings, as a script
    # of theirs would see them.
    child = subprocess.run(
        [sys.executable, "-m", __name__], input=pickle.dumps((what, arguments)), capture_output=True, check=False
    )
    if child.returncode != 0:
        raise RuntimeError(f"the default-settings {what} failed:\n{child.stderr.decode(errors='replace')[-2000:]}")
    return json.loads(child.stdout)


def curve_as_users_call_it(
    scene: Scene, rounds: int = 10, repeats: int = 30, only: tuple[str, ...] | None = None
) -> dict:
    """`curve(scene, rounds, repeats, only)` in a fresh process under JAX's default settings.

    **Arguments:**

    - `scene`: the scene to time (pickled to the child process).
    - `rounds`, `repeats`, `only`: as in `curve`.

    **Returns:** `curve`'s dictionary, with `"async_dispatch"` as the child process had it.
    """
    return _in_a_fresh_process("curve", (scene, rounds, repeats, only))


def fit_as_users_call_it(scene: Scene, loads, stiffness, repeats: int = 15) -> dict:
    """`fitting.fit(loads, stiffness, scene)` (its defaults: BFGS, 12 starts) in a fresh process under
    JAX's default settings: the first call (tracing and compiling its program) and `repeats` more.

    **Returns:** `first_s`, and the later calls' `median_s` and `best_s`.
    """
    return _in_a_fresh_process("fit", (scene, np.asarray(loads), np.asarray(stiffness), repeats))


def _fits(scene: Scene, loads, stiffness, repeats: int) -> dict:
    from jaxcontact import fitting

    from ._curve import stats

    times = []
    for _ in range(repeats + 1):
        start = time.perf_counter()
        fitting.fit(loads, stiffness, scene)
        times.append(time.perf_counter() - start)
    return {"first_s": times[0], **stats(times[1:])}


def _main() -> None:
    import jax

    jax.config.update("jax_enable_x64", True)
    from ._curve import curve

    runs = {
        "curve": lambda scene, rounds, repeats, only: curve(scene, rounds=rounds, repeats=repeats, only=only),
        "fit": _fits,
    }
    what, arguments = pickle.loads(sys.stdin.buffer.read())
    result = runs[what](*arguments)
    result["async_dispatch"] = bool(jax.config.read("jax_cpu_enable_async_dispatch"))
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    _main()
