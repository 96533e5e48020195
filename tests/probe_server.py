"""Real processes for the tests, without a fresh interpreter start-up per request.

Two fork servers, each one fresh interpreter on this checkout, started on first use and kept for
the session:

* :func:`probe_paths` (the *cold* server: nothing imported beyond a fresh ``python -c``; its
  environment ``PYTHONPATH`` and ``PATH`` only) answers "which modules does this code load?".
  A *path* is a list of snippets run one after the other in one process, as the snippets of one
  ``python -c`` script would be; after each, the full ``sys.modules`` and what the snippet printed.
  Paths of one call that begin with the same snippets share those steps: the process forks where
  they part, so each path sees exactly the modules a fresh interpreter running its snippets in
  order would (tests/test_probe_server.py compares a fork's modules with a fresh interpreter's).
* :func:`run_python` (the *warm* server: SymPy, NumPy, mpmath and python-flint imported, then
  ``gc.freeze()``; the test session's environment) runs ``python -m MODULE ARGS`` or
  ``python -c CODE`` as a forked child: a real process with its own exit status and its own
  standard streams (files, read back as ``subprocess.run(..., capture_output=True, text=True)``
  would), whose request runs at the interpreter's top level, so an uncaught exception prints its
  traceback (by ``sys.excepthook``) and exits 1 and ``SystemExit`` sets the status, as in a fresh
  ``python -m``; the child then ends as the interpreter does (threads joined, exit handlers run,
  streams flushed) but by ``os._exit``, without tearing down the preloaded libraries. What it
  cannot show is which modules a request imports (they are loaded before it starts): that is the
  cold server's question. Nothing of this checkout is imported before a request (only third-party
  libraries), so the request imports ``impactsym`` itself, in its own order.

The servers speak over two pipes of their own (length-prefixed ``repr`` of Python literals; module
names joined by spaces, cheap to read back), never over the standard streams, which belong to the
snippets and requests.
"""

from __future__ import annotations

import ast
import atexit
import locale
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import NamedTuple, Sequence

ROOT = Path(__file__).resolve().parents[1]

#: the server, run as ``python -c SERVER CMD_FD REPLY_FD``; it imports nothing a fresh interpreter
#: has not already imported (sys, os, io), so its root process holds exactly a fresh one's modules
SERVER = r'''
import io, os, sys


def _serve():
    cmd_fd, reply_fd = int(sys.argv[1]), int(sys.argv[2])
    ns = {"__name__": "__main__", "__builtins__": __builtins__}

    def read_exactly(n):
        data = b""
        while len(data) < n:
            chunk = os.read(cmd_fd, n - len(data))
            if not chunk:
                os._exit(0)  # the test session has gone: so do we
            data += chunk
        return data

    def read():
        head = b""
        while not head.endswith(b"\n"):
            head += read_exactly(1)
        return eval(read_exactly(int(head)).decode())

    def reply(obj):
        data = repr(obj).encode()
        data = b"%d\n" % len(data) + data
        while data:
            data = data[os.write(reply_fd, data):]

    def run(code):
        saved, sys.stdout = sys.stdout, io.StringIO()
        t = os.times()
        try:
            exec(compile(code, "<probe>", "exec"), ns)
            return ("ok", sys.stdout.getvalue(), " ".join(sys.modules), os.times()[0] - t[0] + os.times()[1] - t[1])
        except BaseException:
            sys.stdout = saved
            import traceback

            return ("error", traceback.format_exc())
        finally:
            sys.stdout = saved

    reply(("ok", "", " ".join(sys.modules)))
    while True:
        cmd = read()
        if cmd[0] == "exec":  # run a snippet in this process
            reply(run(cmd[1]))
        elif cmd[0] == "fork":  # run a snippet in a child, which serves from now on, until "pop"
            pid = os.fork()
            if pid == 0:
                reply(run(cmd[1]))
                continue
            os.waitpid(pid, 0)
            reply(("popped",))
        elif cmd[0] == "pop":
            os._exit(0)
        elif cmd[0] == "run":  # a child that leaves the loop and runs the request as its program
            pid = os.fork()
            if pid == 0:
                os.close(cmd_fd)
                os.close(reply_fd)
                for fd, (path, mode) in enumerate(cmd[2]):
                    f = os.open(path, mode)
                    os.dup2(f, fd)
                    os.close(f)
                return cmd[1]
            t = os.times()
            _, status = os.waitpid(pid, 0)
            reply(("exit", os.waitstatus_to_exitcode(status), os.times()[2] - t[2] + os.times()[3] - t[3]))


def _probe_server_exit(status, sys=sys, os=os):
    # the end of a request's process as the interpreter's own: its threads joined, its exit
    # handlers run, the standard streams flushed (status 120 if that fails); then the process ends
    # without freeing the preloaded libraries object by object (0.03 s of CPU a request)
    threading = sys.modules.get("threading")
    if threading is not None:
        threading._shutdown()
    import atexit

    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            if stream is not None:
                stream.flush()
        except Exception:
            status = 120
    os._exit(status & 0xFF)


_request = _serve()
del _serve
try:
    if _request[0] == "-m":
        import runpy

        sys.argv = ["-m", *_request[2]]
        runpy._run_module_as_main(_request[1])
    else:
        sys.argv = ["-c", *_request[2]]
        exec(compile(_request[1], "<string>", "exec"), {"__name__": "__main__", "__builtins__": __builtins__})
except KeyboardInterrupt:
    raise  # the interpreter ends such a process by SIGINT: let it
except SystemExit as _probe_server_stop:  # as the interpreter reads SystemExit's code
    _code = _probe_server_stop.code
    if _code is not None and not isinstance(_code, int):
        print(_code, file=sys.stderr)
        _code = 1
    _probe_server_exit(_code or 0)
except BaseException:  # an uncaught exception: its traceback by sys.excepthook, status 1
    sys.last_type, sys.last_value, sys.last_traceback = sys.exc_info()
    sys.excepthook(*sys.exc_info())
    _probe_server_exit(1)
else:
    _probe_server_exit(0)
'''


#: what the warm server imports before it serves: third-party libraries only (a request imports this
#: checkout itself); then ``gc.freeze()``, so that a child's collections, and the last one at its
#: exit, do not walk (and copy) the preloaded objects: 0.16 s of CPU a request without, 0.04 s with
WARM_PRELOAD = "import flint, mpmath, numpy, sympy\nimport gc\ngc.freeze()"


class ProbeError(AssertionError):
    """A snippet raised in the probe process (its traceback is the message)."""


class _Server:
    """One server process and its two pipes."""

    def __init__(self, env: dict, preload: str | None = None):
        cmd_r, self.cmd_w = os.pipe()
        self.reply_r, reply_w = os.pipe()
        self.proc = subprocess.Popen([sys.executable, "-c", SERVER, str(cmd_r), str(reply_w)], cwd=ROOT, env=env,
                                     pass_fds=(cmd_r, reply_w), stdin=subprocess.DEVNULL,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        os.close(cmd_r)
        os.close(reply_w)
        self.root_modules = frozenset(self._reply(60)[2].split())
        if preload is not None:
            self.call(("exec", preload))

    def _reply(self, timeout: float):
        head = b""
        while not head.endswith(b"\n"):
            head += self._read(1, timeout)
        return ast.literal_eval(self._read(int(head), timeout).decode())

    def _read(self, n: int, timeout: float) -> bytes:
        data = b""
        while len(data) < n:
            if not select.select([self.reply_r], [], [], timeout)[0]:
                self.kill()
                raise subprocess.TimeoutExpired(self.proc.args[:2], timeout)
            chunk = os.read(self.reply_r, n - len(data))
            if not chunk:
                self.kill()
                raise ProbeError(f"the probe server exited (status {self.proc.wait()})")
            data += chunk
        return data

    def call(self, cmd: tuple, timeout: float = 600):
        data = repr(cmd).encode()
        os.write(self.cmd_w, b"%d\n" % len(data) + data)
        answer = self._reply(timeout)
        if answer[0] == "error":
            self.kill()  # the process that raised is in an unknown state: start afresh next time
            raise ProbeError(answer[1])
        return answer

    def _close_pipe(self, name: str):
        """Close one of our pipe ends once: a number closed twice may by then belong to another
        descriptor of this process (a Jupyter client's zmq socket, which aborts the process when
        its descriptor vanishes)."""
        fd = getattr(self, name)
        if fd is not None:
            setattr(self, name, None)
            os.close(fd)

    def kill(self):
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait()
        self._close_pipe("cmd_w")
        self._close_pipe("reply_r")

    def close(self):
        if self.cmd_w is not None:
            self._close_pipe("cmd_w")  # end of input: the serving process exits, then its parents
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                pass
        self.kill()


_SERVERS: dict = {}
#: the environment of the warm server: the session's, as it was when the tests were collected (a
#: test that changes ``os.environ`` later does not change it for the requests of other tests), with
#: this checkout first on ``PYTHONPATH``
_SESSION_ENV = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))


def _server(kind: str) -> _Server:
    s = _SERVERS.get(kind)
    if s is None or s.proc.poll() is not None:
        if kind == "cold":
            s = _Server({"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
        else:
            s = _Server(_SESSION_ENV, preload=WARM_PRELOAD)
        _SERVERS[kind] = s
    return s


@atexit.register
def _close_servers():
    for s in _SERVERS.values():
        s.close()
    _SERVERS.clear()


class Step(NamedTuple):
    """The state after one snippet of a path: every module in ``sys.modules``, what the snippet
    printed, and the CPU seconds it took (user + system, in its process)."""

    modules: frozenset
    out: str
    cpu: float


def root_modules() -> frozenset:
    """The modules of the cold server's root process (a fresh interpreter's, and nothing else)."""
    return _server("cold").root_modules


def probe_paths(paths: Sequence[Sequence[str]]) -> list[list[Step]]:
    """Run each path (a list of snippets, Python source) in order in a process that began as a fresh
    interpreter; return, for each path, the :class:`Step` after each of its snippets.

    The snippets of a path share one namespace (like one script). Paths that begin with the same
    snippets run those once: a process forks where paths part (depth first), and a snippet runs in
    a process of its own only where another path still needs the state before it.
    """
    paths = [tuple(p) for p in paths]
    trie: dict = {}
    for p in paths:
        node = trie
        for snippet in p:
            node = node.setdefault(snippet, {})
    server = _server("cold")
    results: dict = {}

    def visit(node: dict, prefix: tuple, at_root: bool):
        items = list(node.items())
        for i, (snippet, child) in enumerate(items):
            in_place = i == len(items) - 1 and not at_root  # nobody needs the state before it again
            answer = server.call(("exec" if in_place else "fork", snippet))
            if answer[0] != "ok":
                raise ProbeError(f"the probe process of {snippet!r} died: {answer!r}")
            results[prefix + (snippet,)] = Step(frozenset(answer[2].split()), answer[1], answer[3])
            visit(child, prefix + (snippet,), False)
            if not in_place:
                server.call(("pop",))

    try:
        visit(trie, (), True)
    except BaseException:
        server.kill()
        raise
    return [[results[p[:i + 1]] for i in range(len(p))] for p in paths]


#: the first snippet of a path of command-line requests
REQUEST_PREAMBLE = "import contextlib, io, sys\nfrom impactsym.cli import main"


def request_snippet(argv: Sequence[str], status: int) -> str:
    """A snippet that runs ``main(argv)`` (its output discarded) and asserts its exit status."""
    argv = list(argv)
    return ("with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            f"    assert main({argv!r}) == {status!r}, {argv!r}")


_GROUPS: dict = {}


class RequestProbes:
    """Command-line requests probed for the libraries they load (:func:`probe_paths`): a *trunk* of
    ``(argv, exit status, expected libraries)`` run in order in one process, and *branches*, each
    run after the whole trunk in a fork of its own (so a branch that loads SymPy hides nothing
    from another). A library a request loads stays loaded, so along a path the sets only grow: the
    first request that loads a library is the first whose set shows it. Each path's expected sets
    must therefore grow (else a library an earlier request loads would hide in a later one's set),
    which the constructor checks.

    Probes made with the same ``group`` (of different test modules) that have not run yet run
    together, on one trunk: the members' trunks merged in order of growing expected sets (a
    member's own requests keep their order), then every member's branches after it. A library is
    then imported once for the group, not once per module.
    """

    def __init__(self, trunk, branches=(), libraries=("sympy", "mpmath", "scipy"), group: str | None = None):
        def cases(seq):
            return [(list(argv), status, frozenset(loaded)) for argv, status, loaded in seq]

        self.trunk = cases(trunk)
        self.branches = [cases(b) for b in branches]
        self.libraries = tuple(libraries)
        _check_growth([self.trunk + b for b in self.branches or [[]]])
        self._run_trunk = None  # the trunk that ran: this one's, or its group's
        self._sets = None
        if group is not None:
            _GROUPS.setdefault(group, []).append(self)
        self.group = group

    def paths(self) -> list:
        """The trunk that ran (this probe's, or its group's), then that trunk followed by each branch."""
        self._compute()
        return [self._run_trunk] + [self._run_trunk + b for b in self.branches]

    def _compute(self):
        if self._sets is not None:
            return
        members = [m for m in _GROUPS.get(self.group, []) if m._sets is None] if self.group else [self]
        # stable: each member's trunk keeps its order, merged by the size of the expected sets
        trunk = sorted([c for m in members for c in m.trunk], key=lambda c: len(c[2]))
        _check_growth([trunk + b for m in members for b in m.branches or [[]]])
        paths = [trunk + b for m in members for b in [[]] + m.branches]
        steps = iter(probe_paths([[REQUEST_PREAMBLE] + [request_snippet(a, s) for a, s, _ in p] for p in paths]))
        for m in members:
            m._run_trunk = trunk
            m._sets = [[{lib for lib in m.libraries if lib in step.modules} for step in next(steps)]
                       for _ in [[]] + m.branches]

    def sets(self, path: int = 0) -> list:
        """The libraries loaded before the first request of path ``path`` (0: the trunk that ran;
        ``i``: that trunk and branch ``i - 1``), then after each of its requests."""
        self._compute()
        return self._sets[path]

    def _find(self, argv, status):
        for i, path in enumerate(self.paths()):
            keys = [(a, s) for a, s, _ in path]
            if (list(argv), status) in keys:
                return i, keys.index((list(argv), status)) + 1
        raise KeyError((argv, status))

    def loaded(self, argv, status=0) -> set:
        """The libraries loaded after the first probe of ``(argv, status)``."""
        path, i = self._find(argv, status)
        return self.sets(path)[i]

    def before(self, argv, status=0) -> set:
        """The libraries loaded just before the first probe of ``(argv, status)``."""
        path, i = self._find(argv, status)
        return self.sets(path)[i - 1]


def _check_growth(paths):
    for path in paths:
        for (_, _, a), (_, _, b) in zip(path, path[1:]):
            assert a <= b, "order the probes by growing expected sets"


_SESSION_DIR: list = []


def session_dir() -> Path:
    """A directory for the session's probe inputs and outputs, removed when the session ends."""
    if not _SESSION_DIR:
        _SESSION_DIR.append(Path(tempfile.mkdtemp(prefix="impactsym-probes-")))
        atexit.register(shutil.rmtree, _SESSION_DIR[0], True)
    return _SESSION_DIR[0]


def run_python(args: Sequence[str], *, input: str | None = None, timeout: float | None = None
               ) -> subprocess.CompletedProcess:
    """``subprocess.run([sys.executable, *args], input=input, capture_output=True, text=True)`` for
    ``args`` = ``["-m", MODULE, ...]`` or ``["-c", CODE, ...]``, run by a child of the warm server
    (module docstring): a real process, its exit status and standard streams its own."""
    if len(args) < 2 or args[0] not in ("-m", "-c"):
        raise ValueError(f"run_python takes ['-m', MODULE, ...] or ['-c', CODE, ...], got {args!r}")
    server = _server("warm")
    d = Path(tempfile.mkdtemp(prefix="impactsym-run-"))
    try:
        (d / "in").write_text(input or "", encoding=locale.getpreferredencoding(False))
        streams = [(str(d / "in"), os.O_RDONLY)] + [(str(d / n), os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
                                                     for n in ("out", "err")]
        status = server.call(("run", (args[0], args[1], list(args[2:])), streams),
                             timeout=600 if timeout is None else timeout)[1]
        out, err = ((d / n).read_text(encoding=locale.getpreferredencoding(False)) for n in ("out", "err"))
    finally:
        shutil.rmtree(d, ignore_errors=True)
    return subprocess.CompletedProcess([sys.executable, *args], status, out, err)
