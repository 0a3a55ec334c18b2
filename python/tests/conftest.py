"""Shared fixtures: the checkout's root, the example data and the stfit command line."""

import os
import pathlib
import shutil
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "fits" / "example.csv"


def _cli() -> pathlib.Path:
    """The stfit binary: $STFIT_CLI, else the checkout's own, brought up to date by cargo
    (a no-op after the workspace's build)."""
    given = os.environ.get("STFIT_CLI")
    if given:
        return pathlib.Path(given)
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.skip("no cargo to build the stfit binary (set STFIT_CLI)")
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    if not target.is_absolute():
        target = REPO / target
    subprocess.run([cargo, "build", "--quiet", "--bin", "stfit"], cwd=REPO, check=True)
    return target / "debug" / "stfit"


@pytest.fixture(scope="session")
def cli():
    """Runs the stfit command line from the checkout's root and returns its stdout."""
    exe = _cli()

    def run(*args, stdin=None):
        done = subprocess.run(
            [str(exe), *args], cwd=REPO, input=stdin, capture_output=True, text=True, check=True
        )
        return done.stdout

    return run


@pytest.fixture
def at_repo(monkeypatch):
    """Runs the test from the checkout's root, so relative data paths read as the CLI's."""
    monkeypatch.chdir(REPO)
    return REPO
