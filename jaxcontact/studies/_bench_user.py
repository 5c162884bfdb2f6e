"""The 200-load curve of `jaxcontact bench` timed as a user's process runs it: JAX's default settings.

The command line runs compiled calls synchronously (`cli._process.command_settings`), and JAX reads
that setting only when it creates its CPU client, so the bench process cannot time the calls as a
notebook or a script makes them. This module times `curve` (scipy and every jaxcontact call,
interleaved, in the same run) in a fresh Python process that switches float64 on and nothing else:
asynchronous dispatch, no persistent compilation cache, no stored programs.

Run as `python -m jaxcontact.studies._bench_user`: a pickled `(scene, rounds, repeats, only)` on stdin,
the curve's results as JSON on stdout.
"""

from __future__ import annotations

import json
import pickle
import subprocess
import sys

from ..core import Scene


def curve_as_users_call_it(
    scene: Scene, rounds: int = 10, repeats: int = 30, only: tuple[str, ...] | None = None
) -> dict:
    """`curve(scene, rounds, repeats, only)` in a fresh process under JAX's default settings.

    **Arguments:**

    - `scene`: the scene to time (pickled to the child process).
    - `rounds`, `repeats`, `only`: as in `curve`.

    **Returns:** `curve`'s dictionary, with `"async_dispatch"` as the child process had it.
    """
    # The environment is inherited: JAX_ and XLA_ variables are the user's settings, as a script
    # of theirs would see them.
    child = subprocess.run(
        [sys.executable, "-m", __name__],
        input=pickle.dumps((scene, rounds, repeats, only)),
        capture_output=True,
        check=False,
    )
    if child.returncode != 0:
        raise RuntimeError(f"the default-settings curve failed:\n{child.stderr.decode(errors='replace')[-2000:]}")
    return json.loads(child.stdout)


def _main() -> None:
    import jax

    jax.config.update("jax_enable_x64", True)
    from ._curve import curve

    scene, rounds, repeats, only = pickle.loads(sys.stdin.buffer.read())
    result = curve(scene, rounds=rounds, repeats=repeats, only=only)
    result["async_dispatch"] = bool(jax.config.read("jax_cpu_enable_async_dispatch"))
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    _main()
