"""Fixtures for the carom Python tests.

CTest sets the environment (python/CMakeLists.txt): PYTHONPATH (the assembled package),
CAROM_EXE (the command line the module is compared against) and CAROM_SOURCE_DIR (the reference
cases and examples). Tests write only into pytest's tmp_path, and never depend on the working
directory.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest


def _drop_source_packages_from_path():
    """`python -m pytest` puts the working directory first on sys.path; run from python/, the
    source package carom/ there (no compiled _carom) would shadow the built one on PYTHONPATH."""
    for entry in list(sys.path):
        package = Path(entry or os.getcwd()) / "carom"
        if (package / "__init__.py").is_file() and not any(package.glob("_carom*")):
            sys.path.remove(entry)


_drop_source_packages_from_path()

import carom  # noqa: E402,F401  (fail early, and clearly, if the module does not import)

SOURCE_DIR = Path(os.environ.get("CAROM_SOURCE_DIR") or Path(__file__).resolve().parents[2])
CASES = SOURCE_DIR / "tests" / "data" / "cases"
EXAMPLES = SOURCE_DIR / "examples"


class Cli:
    """Runs the `carom` command line and returns its stdout (bytes decoded, newlines untouched)."""

    def __init__(self, exe):
        self.exe = exe

    def run(self, *args, expect=0, cwd=None):
        command = [self.exe, *[str(a) for a in args]]
        proc = subprocess.run(command, capture_output=True, cwd=cwd, timeout=300)
        # A message may name a file whose name is not UTF-8: decoded as os.fsdecode decodes one.
        out = proc.stdout.decode(errors="surrogateescape")
        err = proc.stderr.decode(errors="surrogateescape")
        assert proc.returncode == expect, (
            f"{' '.join(command)} exited with {proc.returncode}, expected {expect}:\n{err}")
        self.last_stderr = err
        return out

    __call__ = run

    def error(self, *args, expect=2):
        """A failing command's error message: its first stderr line, after 'carom: error: '."""
        self.run(*args, expect=expect)
        first = self.last_stderr.splitlines()[0]
        prefix = "carom: error: "
        assert first.startswith(prefix), self.last_stderr
        return first[len(prefix):]


@pytest.fixture(scope="session")
def cli():
    exe = os.environ.get("CAROM_EXE")
    if not exe:
        pytest.skip("CAROM_EXE is not set: it names the carom executable (CTest sets it)")
    assert Path(exe).is_file(), f"CAROM_EXE={exe} is not a file"
    return Cli(exe)


@pytest.fixture(scope="session")
def cases():
    assert CASES.is_dir(), f"no reference cases at {CASES}: set CAROM_SOURCE_DIR"
    return CASES


@pytest.fixture(scope="session")
def examples():
    assert EXAMPLES.is_dir(), f"no examples at {EXAMPLES}: set CAROM_SOURCE_DIR"
    return EXAMPLES
