"""Notebooks are tests (galgebra's habit): each one runs top to bottom without error, and is
committed without outputs (the policy in notebooks/README.md).

The notebooks run in one real Jupyter kernel (nbclient, ``python3``), started once for the module:
before each notebook the kernel's figures are closed and its namespace is reset (``%reset -f``), so
a notebook that forgets an import or a definition still fails; matplotlib's global state (backend,
rcParams, IPython's inline integration) is put back as a fresh kernel has it (:data:`RESET_MATPLOTLIB`).
What the kernel keeps between notebooks is only what Python itself caches (imported modules), which
spares each notebook the kernel start and the imports of SymPy, NumPy and impactsym.
"""

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

from impactsym.cli.reproduce import AUDIT_GC_THRESHOLDS

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))

#: run before every notebook: no open figure and an empty namespace (a fresh kernel's state). Figures
#: are closed only where pyplot was imported (a fresh kernel has not imported it). The namespace is
#: emptied by IPython's own ``%reset -f``, which collects garbage twice (once as it flushes the output
#: cache, before the namespace is emptied, and once after): it runs with ``gc.collect`` deferred, and
#: one full collection follows it, which frees all that both would have freed (the closed figures
#: included); the first one, a walk of every object the notebook before had made, was about 0.35 s
#: of the kernel's CPU in all. The objects that survive (modules, caches) are then frozen
#: (``gc.freeze``), so that the next notebook's collections, the next reset's included, walk only the
#: objects made since. Two resets, each a full collection of a heap grown by every notebook before
#: it, were about 0.4 s of the kernel's CPU per notebook.
#:
#: Matplotlib keeps a global state a notebook changes: the backend (``impactsym.figures`` selects
#: Agg), the rcParams, and IPython's inline integration, which the inline backend sets up when it is
#: first loaded (interactive mode, a hook that shows the figures left open after a cell). A fresh
#: kernel finds the rcParams of the files and the backend the kernel asks for (``MPLBACKEND``: the
#: inline one), chosen by pyplot at its first figure. Left as an earlier notebook had set it, a
#: notebook's ``plt.show()`` showed nothing (engines.ipynb, after a figure notebook had selected Agg).
#: So the reset restores that: the rcParams as matplotlib read them, the kernel's backend, pyplot's
#: backend left to choose again at the next figure, and the inline integration taken down (its module
#: dropped, so that loading the inline backend again sets it up again, as in a fresh kernel).
RESET_MATPLOTLIB = """\
import sys as _sys
if 'matplotlib' in _sys.modules:
    import os as _os
    _mpl = _sys.modules['matplotlib']
    if 'matplotlib.pyplot' in _sys.modules:
        _plt = _sys.modules['matplotlib.pyplot']
        _plt.close('all')
        _plt.uninstall_repl_displayhook()  # installed again with the backend
        _plt._backend_mod = None  # the backend chosen again at the next figure
        del _plt
    if 'matplotlib_inline.backend_inline' in _sys.modules:  # its hook off, no figure formatter
        _sys.modules.pop('matplotlib_inline.backend_inline').configure_inline_support(get_ipython(), 'agg')
        for _f in get_ipython().display_formatter.formatters.values():
            _f.pop(_sys.modules['matplotlib.figure'].Figure, None)
    _mpl.rcParams.update(_mpl.rcParamsOrig)
    if _os.environ.get('MPLBACKEND'):
        _mpl.rcParams['backend'] = _os.environ['MPLBACKEND']
    del _os, _mpl
del _sys
"""
RESET = (RESET_MATPLOTLIB +
         "import gc as _gc\n"
         "_gc._collect_all, _gc.collect = _gc.collect, lambda generation=2: 0\n"
         "try:\n"
         "    get_ipython().run_line_magic('reset', '-f')\n"
         "finally:\n"
         "    import gc as _gc\n"
         "    _gc.collect = _gc.__dict__.pop('_collect_all')\n"
         "_gc.collect()\n"
         "_gc.freeze()\n"
         "del _gc")


def test_there_are_notebooks():
    assert NOTEBOOKS, "notebooks/ holds no notebook"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_committed_without_outputs(path):
    nb = nbformat.read(path, as_version=4)
    dirty = [i for i, c in enumerate(nb.cells) if c.cell_type == "code" and (c.outputs or c.execution_count)]
    assert not dirty, f"{path.name}: cells {dirty} carry outputs; strip them before committing"


def _execute(nb, kernel, **options):
    """Run ``nb`` in the shared kernel, then stop the client's channels: nbclient leaves them
    running when it does not own the kernel, and each left behind keeps a heartbeat thread
    polling its zmq sockets for the rest of the session."""
    client = NotebookClient(nb, km=kernel, **options)
    try:
        client.execute()
    finally:
        if client.kc is not None:
            client.kc.stop_channels()


@pytest.fixture(scope="module")
def kernel():
    """One python3 kernel, started in the repository root (where every notebook runs), for the module.

    Its input history is off (``HistoryManager.enabled=False``): nothing here reads it, and it
    would write every cell into the user's ``~/.ipython`` history database (about 1.5 ms of the
    kernel's CPU per cell).

    It collects cyclic garbage at the test process's thresholds (the audit's
    :data:`~impactsym.cli.reproduce.AUDIT_GC_THRESHOLDS`; CPython's default is (700, 10, 10)): the
    notebooks' SymPy work (unbounded cache, inherited ``SYMPY_CACHE_SIZE``) and figures allocate
    millions of objects beside a heap that grows with each notebook, which the default thresholds
    walk again and again. A notebook's outputs do not depend on when garbage is collected. The
    kernel's CPU for the six notebooks, alternating runs: 8.59 and 7.80 s with the default (1084
    generation-0, 95 generation-1 and 11 full collections), 8.07 and 7.44 s with these (141, 11, 7)."""
    from jupyter_client.manager import KernelManager

    km = KernelManager(kernel_name="python3")
    km.start_kernel(cwd=str(ROOT), extra_arguments=["--HistoryManager.enabled=False"])
    _execute(nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(
        f"import gc\ngc.set_threshold(*{AUDIT_GC_THRESHOLDS!r})\ndel gc")]), km, timeout=60)
    yield km
    km.shutdown_kernel(now=True)


def test_reset_leaves_no_name_behind(kernel):
    """The reset really empties the namespace: a name defined by one notebook is gone for the next."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("leftover = 1")])
    _execute(nb, kernel, timeout=60)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(RESET),
                                         nbformat.v4.new_code_cell("leftover")])
    _execute(nb, kernel, timeout=60, allow_errors=True)
    errors = [o for o in nb.cells[1].outputs if o.output_type == "error"]
    assert errors and errors[0].ename == "NameError"


def test_the_kernel_collects_at_the_test_process_thresholds(kernel):
    """The kernel's garbage-collector thresholds are the test process's, and the reset keeps them."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(RESET),
                                         nbformat.v4.new_code_cell("import gc\nprint(gc.get_threshold())")])
    _execute(nb, kernel, timeout=60)
    assert [o.text for o in nb.cells[1].outputs] == [f"{AUDIT_GC_THRESHOLDS}\n"]


def test_reset_gives_the_kernels_backend_back(kernel):
    """After a notebook that built a figure of impactsym.figures (which selects Agg), the next one's
    ``plt.show()`` shows its figure, as in a fresh kernel (the inline backend)."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(
        "import impactsym.figures as F\nfig, src = F.sm_fig1_convex_corner()")])
    _execute(nb, kernel, timeout=60)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(RESET), nbformat.v4.new_code_cell(
        "import matplotlib.pyplot as plt\nplt.figure(figsize=(1, 1)).add_axes((0, 0, 1, 1)).set_axis_off()\nplt.show()")])
    _execute(nb, kernel, timeout=60)
    assert [o.output_type for o in nb.cells[1].outputs] == ["display_data"]
    assert "image/png" in nb.cells[1].outputs[0].data


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_executes(path, kernel):
    nb = nbformat.read(path, as_version=4)
    nb.cells.insert(0, nbformat.v4.new_code_cell(RESET))
    _execute(nb, kernel, timeout=600)
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors
