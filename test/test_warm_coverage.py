"""The set-up's warm-up (``python -m tether_sim.warm``, run by ``make setup``) compiles every kernel a
shipped configuration's node uses, so that no node's first start after an install compiles.

numba compiles a kernel once per signature (argument types; a read-only array is a type of its own)
and caches each signature on disk: a node's start loads from the cache exactly the signatures the
warm-up compiled. So the check compares signatures, not timings: after the warm-up groups have run
in this process, running the start of each shipped configuration (``tether_sim:`` files in config/;
single lines as the node's warm-up runs them, line networks as their node does,
:func:`tether_sim.warm.exercise_network`) must add no signature to any kernel of ``tether_sim``.
With a warm cache (``make setup`` did it) this is a cache load, a few seconds.
"""

import sys
from pathlib import Path

import numba
import pytest

from tether_sim import warm

ROOT = Path(__file__).resolve().parent.parent
pytestmark = pytest.mark.skipif(numba.config.DISABLE_JIT, reason="no kernels are compiled with the JIT off")


def compiled_signatures() -> set:
    """(module, function, signature) of every signature of the numba kernels in the loaded tether_sim modules."""
    from numba.core.dispatcher import Dispatcher

    found = set()
    for name, module in sys.modules.copy().items():
        if not name.startswith("tether_sim") or module is None:
            continue
        for value in list(vars(module).values()):
            if isinstance(value, Dispatcher):
                f = value.py_func
                found.update((f.__module__, f.__qualname__, str(sig)) for sig in value.signatures)
    return found


def shipped_configurations() -> list:
    return sorted(p for p in (ROOT / "config").glob("*.yaml") if "tether_sim:" in p.read_text())


def start_of(path):
    """What a node started with ``path`` runs before and in its first ticks (module doc)."""
    from tether_sim.io.params import load_config
    from tether_sim.network.params import file_is_network

    if file_is_network(path):
        warm.exercise_network(path)
    else:
        warm.exercise(load_config(path))


@pytest.mark.slow  # ~20 starts from the cache: 86 s at load 6, nice 19 (2026-11-28)
def test_the_warm_up_covers_every_shipped_configuration():
    warm.warm_groups(out=lambda text: None)
    covered = compiled_signatures()
    assert covered, "the warm-up compiled no kernel"
    configs = shipped_configurations()
    assert len(configs) >= 15 and ROOT / "config/ropos_tms.yaml" in configs
    missing = {}
    for path in configs:
        start_of(path)
        new = compiled_signatures() - covered
        if new:
            missing[path.name] = sorted(f"{m}.{f}{s}" for m, f, s in new)
            covered |= new
    assert not missing, "kernels the warm-up (tether_sim/warm.py GROUPS) does not compile:\n" + "\n".join(
        f"{name}: {', '.join(kernels)}" for name, kernels in missing.items())


def test_the_check_sees_a_kernel_the_warm_up_left_out():
    """After the single-line DG group alone (the TMS file's tether is a DG line with a body end), the
    TMS file's start adds kernels of its own (the bodies' coupling step at least): the check above
    can fail (it did, for the TMS file, the Goyal & Perkins rod and the ROV demo's statics, before
    their groups were added)."""
    groups = [g for g in warm.GROUPS if g[1] == "config/ropos_validation.yaml"]
    assert len(groups) == 1
    # in a fresh process: this one may have run the network group already
    import subprocess

    code = ("import sys; sys.path.insert(0, 'test'); from tether_sim import warm; import test_warm_coverage as t; "
            f"warm.warm_groups({groups!r}, out=lambda text: None); before = t.compiled_signatures(); "
            "warm.exercise_network(t.ROOT / 'config/ropos_tms.yaml'); "
            "new = t.compiled_signatures() - before; print(sorted(f for _, f, _ in new))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert "kdk_open" in out and "kdk_close" in out, out


def test_a_forecast_members_tick_compiles_nothing_after_the_warm_up():
    """The snap forecast runs its members with the interface's one-call tick (``solver.tick`` with the ship's
    motion as two arrays: the compiled ``tick.ship_tick``), which the node's own ticks (``advance_to``) do not
    use; without it in the warm-up the first forecast of a live node compiled that kernel (seconds, in the
    forecast's worker thread). After the single-line DG group, a tick of the forecast file's solver adds no
    signature (in a fresh process: this one may have run other groups)."""
    groups = [g for g in warm.GROUPS if g[1] == "config/ropos_validation.yaml"]
    import subprocess

    code = ("import sys; sys.path.insert(0, 'test'); import numpy as np; from tether_sim import warm; "
            "import test_warm_coverage as t; from tether_sim.io.params import load_config; "
            "from tether_sim.solvers.factory import build_solver; "
            f"warm.warm_groups({groups!r}, out=lambda text: None); before = t.compiled_signatures(); "
            "cfg = load_config(t.ROOT / 'config/ropos_forecast.yaml'); s = build_solver(cfg); "
            "p = np.asarray(cfg.ship_end.position, dtype=np.float64); "
            "s.tick(0.02, ship=(p + 0.01, np.array([0.0, 0.0, 0.5]))); "
            "new = t.compiled_signatures() - before; print(sorted(f for _, f, _ in new))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert out.strip().splitlines()[-1] == "[]", out
