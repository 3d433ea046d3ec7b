"""'compiling kernels (first run only)...' prints only when numba compiles, and the report says
the cache was cold only then (issue 22, item 6). On a warm cache numba still fires two compile
events per metro run (rhs_call and _outputs ask for their model kind as a literal: each event ends
at once with ForceLiteralArg, 6 ms, and the literal kernel loads from the disk cache)."""

import subprocess
import sys
import time

import pytest

import railwear
from railwear import cli


class Event:
    """A numba event as the listener sees it: its exception details set when it failed (numba
    0.68's is_failed reads them the other way round, so the listener reads them itself)."""

    def __init__(self, name, failed=False):
        self.data = {"dispatcher": type("Dispatcher", (), {"__name__": name})()}
        self._exc_details = (RuntimeError, RuntimeError("ForceLiteralArg"), None) if failed else None


@pytest.fixture
def notice(monkeypatch):
    monkeypatch.setitem(cli._compile_notice, "printed", False)
    monkeypatch.setitem(cli._compile_notice, "compiled", False)
    monkeypatch.setitem(cli._compile_notice, "progress", None)
    said = []
    return cli.compile_listener(delay=0.05, echo=said.append), said


def test_the_exception_is_read_from_numbas_own_event():
    from numba.core import event

    failed = event.Event("numba:compile", event.EventStatus.END, exc_details=(KeyError, KeyError("x"), None))
    done = event.Event("numba:compile", event.EventStatus.END)
    assert cli._failed(failed) and not cli._failed(done)


def test_an_event_that_ends_at_once_without_compiling_says_nothing(notice):
    listener, said = notice
    for name in ("rhs_call", "_outputs"):
        listener.on_start(Event(name))
        listener.on_end(Event(name, failed=True))  # ForceLiteralArg: then loaded from the cache
    time.sleep(0.15)
    assert said == [] and not cli._compile_notice["printed"] and not cli._compile_notice["compiled"]


def test_a_compile_that_goes_on_prints_the_notice_once(notice):
    listener, said = notice
    listener.on_start(Event("advance"))
    time.sleep(0.2)
    listener.on_end(Event("advance"))
    listener.on_start(Event("rates"))
    time.sleep(0.2)
    listener.on_end(Event("rates"))
    assert said == ["compiling kernels (first run only)..."]
    assert cli._compile_notice["compiled"]


def test_a_quick_compile_is_a_compile_for_the_report_but_prints_nothing(notice):
    listener, said = notice
    listener.on_start(Event("small"))
    listener.on_end(Event("small"))
    assert said == [] and cli._compile_notice["compiled"]


@pytest.mark.e2e
def test_a_warm_run_says_nothing_of_compiling(tmp_path):
    railwear.run("metro")  # the cache warm for the process below (a cold one compiles here, as any metro test)
    done = subprocess.run([sys.executable, "-m", "railwear", "run", "metro", "--no-figures", "-o", str(tmp_path)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "compiling" not in done.stderr, done.stderr
    report = (tmp_path / "report.html").read_text()
    assert "numba compiled kernels" not in report and "cold cache" not in report
