"""Shared fixtures: the repository root (the tests run from anywhere) and the CLI binary the
results are compared with (TELESCOPIC_BIN, else target/debug/telescopic)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    """Scene paths are relative to the repository root."""
    monkeypatch.chdir(ROOT)


@pytest.fixture(autouse=True)
def no_budget_records(monkeypatch):
    """Runs keep no error budgets for reuse between tests (the library's and the CLI's);
    the tests of reuse name a directory of their own."""
    monkeypatch.setenv("TELESCOPIC_CACHE_DIR", "off")


@pytest.fixture(scope="session")
def cli():
    """Runs the `telescopic` binary; a missing binary fails the test, naming it."""
    binary = os.environ.get("TELESCOPIC_BIN", str(ROOT / "target" / "debug" / "telescopic"))
    if not os.path.exists(binary):
        pytest.fail(f"the telescopic binary {binary} is missing: cargo build (or set TELESCOPIC_BIN)")

    def run(*args):
        out = subprocess.run([binary, *args], cwd=ROOT, capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        return out

    return run
