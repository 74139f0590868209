"""Shared helpers of the gmslab Python tests: the module, the CLI executable and temp paths."""
import os
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PRESETS = os.path.join(ROOT, "presets")


@pytest.fixture(scope="session")
def cli():
    """Runs the gmslab command line (GMSLAB_EXE); the test is skipped when it was not built."""
    exe = os.environ.get("GMSLAB_EXE", "")
    if not exe or not os.access(exe, os.X_OK):
        pytest.skip("gmslab executable not built (GMSLAB_EXE unset)")

    def run(*args, check=True):
        p = subprocess.run([exe, *args], capture_output=True, text=True, timeout=300)
        if check and p.returncode != 0:
            raise AssertionError(f"gmslab {' '.join(args)} failed ({p.returncode}): {p.stderr}")
        return p

    return run
