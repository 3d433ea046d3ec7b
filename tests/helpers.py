"""Helpers shared by the tests (the root conftest puts this folder on the path)."""

import contextlib
import io
import re
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"


def doc_blocks(name):
    """The Python blocks of ``docs/NAME``."""
    return re.findall(r"```python\n(.*?)```", (DOCS / name).read_text(encoding="utf-8"), flags=re.S)


def run_doc_block(code, label):
    """Run a doc block; returns ``(printed, expected)``: the printed lines and what the block says
    it prints (the comment after a ``print(...)`` line, and ``# `` lines right after a print)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, label, "exec"), {})
    expected, after_print = [], False
    for line in code.splitlines():
        stripped = line.strip()
        if stripped.startswith("print("):
            after_print = True
            if "  # " in line:
                expected.append(line.split("  # ", 1)[1].strip())
        elif after_print and stripped.startswith("# "):
            expected.append(stripped[2:].strip())
        elif stripped and not stripped.startswith("#") and not line.startswith((" ", "\t")):
            after_print = False
    return [line.strip() for line in out.getvalue().splitlines()], expected


def doc_script(name):
    """The module of the figure script ``docs/NAME`` (loaded, not run)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(Path(name).stem, DOCS / name)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Killed(Exception):
    """Stands for the process being killed."""


def killed_after(k, saved):
    """A checkpoint callable that keeps every checkpoint in ``saved`` and kills the run (raises
    :class:`Killed`) after the ``k``-th."""
    def keep(cp):
        saved.append(cp)
        if len(saved) == k:
            raise Killed
    return keep


COMPILE_COUNTER = """
import json
import numpy as np
from numba.core import event
from numba.core.dispatcher import Dispatcher

compiled = []

class Count(event.Listener):
    def on_start(self, ev):
        compiled.append(getattr(ev.data.get("dispatcher"), "__name__", "?"))

    def on_end(self, ev):  # numba's listeners must have it; only the starts are counted
        return None

event.register("numba:compile", Count())
"""


def cold_probe(body, cache_dir):
    """Run ``body`` after :data:`COMPILE_COUNTER` in a fresh interpreter with an empty numba cache
    at ``cache_dir``; ``body`` prints one JSON line last (``compiled``: the kernels whose compile
    started, in order), returned parsed."""
    import json
    import os
    import subprocess
    import sys

    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir))
    done = subprocess.run([sys.executable, "-c", COMPILE_COUNTER + body], env=env, capture_output=True,
                          text=True, check=True)
    return json.loads(done.stdout.splitlines()[-1])
