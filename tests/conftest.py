"""The probe servers (tests/probe_server.py) are children of the test process for the whole
session; stop them when the session finishes, before the other session-finish hooks run, so that
their CPU (every probe and real-process request of the session) is in the session's accounting
(``resource.getrusage(RUSAGE_CHILDREN)``) as a fresh process per request was."""

import sys

import pytest


@pytest.hookimpl(tryfirst=True)
def pytest_sessionfinish(session):
    probe_server = sys.modules.get("probe_server")
    if probe_server is not None:
        probe_server._close_servers()
