"""Shared hooks. mpmath's precision is global state: reset it after every test (mpmath's own
habit), so one test's workdps can never leak into another's reference."""

# The test process runs the audit in-process (tests/test_cli_reproduce, paper_checks) and derives
# much of it again in other modules: give it the CLI's unbounded SymPy cache, set the CLI's way and
# before anything imports SymPy (measured: the default run's CPU 148 -> 138 s, peak RSS 0.5 GB).
# SYMPY_CACHE_SIZE set in the environment still wins.
from impactsym.cli.reproduce import AUDIT_GC_THRESHOLDS, use_audit_sympy_cache

use_audit_sympy_cache()

# The cyclic garbage collector: SymPy's cache and the audit's memo keep a large heap of long-lived
# objects alive, and with CPython's default thresholds (700, 10, 10) the run spent about 7 s of CPU
# in collections, 5.5 s of it in about 40 full ones. Collecting less often (gen0 every 50,000 net
# container allocations, full collections a tenth as often: the audit's AUDIT_GC_THRESHOLDS) measured
# 3.3 s, peak RSS 0.50 -> 0.53 GB. Nothing is left uncollected: only the collections are fewer. The
# notebooks' kernel collects with the same thresholds (tests/test_notebooks.py).
import atexit  # noqa: E402
import gc  # noqa: E402
import sys  # noqa: E402

gc.set_threshold(*AUDIT_GC_THRESHOLDS)

import mpmath  # noqa: E402
import pytest  # noqa: E402


@pytest.hookimpl(wrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """Each test's run (its set-up, call and tear-down) leaves mpmath's precision as it found it: a
    hook, not an autouse fixture, which cost about 0.07 ms a test more (fixture set-up and
    finalizer for each of the ~3770 tests; measured on 4000 trivial tests: 3.57 -> 3.38 s CPU, 3.27
    without either). No fixture of a wider scope sets the precision, so every test starts at the
    session's precision, as with the fixture."""
    saved = mpmath.mp.prec
    try:
        return (yield)
    finally:
        mpmath.mp.prec = saved


# Hypothesis: derandomized, so CI explores the same examples (and takes the same time) on every
# run; a failure found here is reproducible and gets pinned with @example. Set
# IMPACTSYM_HYPOTHESIS_RANDOM=1 to explore fresh examples locally.
import os

from hypothesis import settings

settings.register_profile("impactsym-ci", derandomize=True, print_blob=True)
settings.register_profile("impactsym-explore", derandomize=False, print_blob=True)
settings.load_profile("impactsym-explore" if os.environ.get("IMPACTSYM_HYPOTHESIS_RANDOM") else "impactsym-ci")


def pytest_collection_finish(session):
    """Freeze what collection built (modules, fixtures' definitions, parametrizations): it lives to
    the end of the run, and the collector's full passes no longer walk it."""
    gc.collect()
    gc.freeze()


@pytest.hookimpl(tryfirst=True)
def pytest_unconfigure(config):
    """One full collection at the end of the run, then freeze what survives it, before pytest's own
    end-of-run collections (one as its unraisable-exception plugin unconfigures, one in its cleanup)
    look for finalizers that raise. Whatever those two would have freed, this one frees (its
    unraisable exceptions go to pytest's hook, still installed, and are reported as before); they
    then walk only what was made since, instead of the whole heap of the run (SymPy's cache, the
    audit's memo): two full passes of about 0.4 s of CPU each after the full run were one."""
    gc.collect()
    gc.freeze()


@pytest.hookimpl(wrapper=True)
def pytest_cmdline_main(config):
    """The run from the command line (``pytest``, ``python -m pytest``) ends without the
    interpreter's teardown: once the session is over (every hook and cleanup of pytest has run, the
    probe servers and every other child have been waited for) the process exits with pytest's
    status from the last exit handler (:func:`_exit_now`), instead of freeing, object by object,
    the large heap SymPy's cache and the audit's memo have built (measured: about 0.75 s of CPU
    after two modules' run, more after the full run's). ``pytest.main()`` called by other code,
    whose process goes on, is left alone."""
    status = yield
    if any(f.f_code is _CONSOLE_MAIN for f in _frames()):
        sys.stdout.flush()  # a closed pipe raises here, as in pytest's own flush (it then exits 1)
        atexit.register(_exit_now, int(status))
    return status


def _frames():
    f = sys._getframe()
    while f is not None:
        yield f
        f = f.f_back


try:  # the command line's entry point (both ``pytest`` and ``python -m pytest`` call it)
    from _pytest.config import _console_main

    _CONSOLE_MAIN = _console_main.__code__
except ImportError:  # another pytest: the interpreter ends as usual
    _CONSOLE_MAIN = None


def _exit_now(status: int):
    """Registered last, so called first at exit: the other exit handlers (registered before, by
    pytest, the libraries and tests/probe_server.py) run now, in their order; then the standard
    streams are flushed and the process exits with ``status`` (the interpreter's threads were
    joined before any exit handler ran). If the streams cannot be flushed now, the interpreter ends
    as usual."""
    atexit.unregister(_exit_now)
    atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except Exception:
        return
    os._exit(status)
