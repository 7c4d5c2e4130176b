"""Where a study's runs go: an address that is not a Dask scheduler, an empty address, and a
SIGTERM while the local Dask cluster starts (one line, no traceback, the lock released)."""

from __future__ import annotations

import http.server
import socket
import subprocess
import sys
import textwrap
import threading

import pytest

from ringlube import InputError, RinglubeError
from ringlube.executor import Executor

from conftest import COLD

pytestmark = pytest.mark.unit


@pytest.fixture()
def silent_socket():
    """A port that accepts connections and never says anything."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        sock.listen(8)
        yield sock.getsockname()[1]


class _QuietHandler(http.server.BaseHTTPRequestHandler):
    """Answers HTTP requests (as an error page); a client that connects and never sends a
    request (Dask's comm, which waits for the other side to speak first) is dropped after 2 s
    instead of holding the server's only thread, which hung the fixture's shutdown."""

    timeout = 2.0

    def log_message(self, format, *args):  # noqa: A002 - the base class's signature
        pass


@pytest.fixture()
def http_server():
    """A port with an HTTP server (answers, but not as Dask)."""
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _QuietHandler)
    server.daemon_threads = True
    server.block_on_close = False
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


def bounded(fn, *args, seconds: float = 60):
    """``fn(*args)`` in a thread, failing the test if it has not returned after ``seconds``
    (a bound on a hang, not a timing: the answers here are due after 1 s)."""
    done = {}

    def call():
        try:
            done["value"] = fn(*args)
        except Exception as exc:
            done["error"] = exc

    t = threading.Thread(target=call, daemon=True)
    t.start()
    t.join(timeout=seconds)
    assert not t.is_alive(), f"{fn.__name__}{args} still waiting after {seconds} s"
    return done


def test_silent_socket_is_not_taken_for_a_scheduler(silent_socket):
    done = bounded(lambda: Executor(scheduler=f"tcp://127.0.0.1:{silent_socket}", connect_timeout=1))
    assert isinstance(done.get("error"), RinglubeError)
    assert f"tcp://127.0.0.1:{silent_socket}: cannot connect within 1 s" in str(done["error"])


@pytest.mark.parametrize("scheme", ["tcp", "ws"])
def test_http_server_is_not_taken_for_a_scheduler(http_server, scheme, tmp_path, monkeypatch):
    import ringlube.executor

    monkeypatch.setattr(ringlube.executor, "CONNECT_TIMEOUT_S", 1.0)
    done = bounded(lambda: Executor(scheduler=f"{scheme}://127.0.0.1:{http_server}"))
    assert isinstance(done.get("error"), RinglubeError), done
    assert "\n" not in str(done["error"]) and "cannot connect within 1 s" in str(done["error"])


def test_empty_scheduler_address_is_refused():
    with pytest.raises(InputError, match="--scheduler '': empty address"):
        Executor(scheduler="")


@pytest.mark.slow
def test_sigterm_during_cluster_start_ends_quietly(tmp_path):
    deck = tmp_path / "s.nml"
    deck.write_text(
        f"&study\n cases = '{COLD}'\n labels = 'cold'\n samples = 24\n"
        " variables = 'width', 'crown_offset'\n lower = 0.8e-3, -40e-6\n upper = 1.2e-3, 40e-6\n/\n"
    )
    out = tmp_path / "out"
    script = textwrap.dedent(
        f"""
        import os, signal, sys
        from distributed.deploy.spec import SpecCluster
        from ringlube.cli import main

        correct_state = SpecCluster._correct_state_internal

        sent = []

        async def sigterm_while_workers_start(self):  # the batch system's SIGTERM, mid start-up
            if not sent:
                sent.append(os.kill(os.getpid(), signal.SIGTERM))
            return await correct_state(self)

        SpecCluster._correct_state_internal = sigterm_while_workers_start
        sys.exit(main(["optimise", {str(deck)!r}, "--out", {str(out)!r}, "--workers", "1", "-q"]))
        """
    )
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert p.returncode == 130, p.stderr
    assert "Traceback" not in p.stderr and "Error" not in p.stderr, p.stderr
    assert p.stderr.strip().splitlines() == [
        "ringlube: interrupted; finished work is saved (run the same command to resume)"
    ]
    assert not (out / "s.h5.lock").exists()


def test_two_local_clusters_start_without_a_port_warning():
    import warnings

    with socket.socket() as busy, warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        try:  # the port a second study finds taken (here by this socket, or by anyone else)
            busy.bind(("0.0.0.0", 8787))
            busy.listen(1)
        except OSError:
            pass
        with Executor(workers=1, backend="dask"):
            pass
    assert not [w for w in seen if "8787" in str(w.message)], [str(w.message) for w in seen]
