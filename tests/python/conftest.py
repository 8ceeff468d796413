# The pytest suite of the Python module (ctest -L python runs it; see
# docs/python.md). ctest sets WAVEPATH_PYTHON_DIR (the build's python/
# folder, which holds the module) and WAVEPATH (the command line, which the
# module's results are checked against); run by hand from the repository:
#   WAVEPATH_PYTHON_DIR=build/python WAVEPATH=build/wavepath /usr/bin/python3 -m pytest tests/python
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, os.environ.get("WAVEPATH_PYTHON_DIR", str(ROOT / "build" / "python")))

import wavepath  # noqa: E402

CORNELL = str(ROOT / "scenes" / "cornell-box.json")
DATA = ROOT / "tests" / "data"


def cli(*args):
    """Runs the command line; returns (exit status, stderr)."""
    exe = os.environ.get("WAVEPATH", str(ROOT / "build" / "wavepath"))
    p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, timeout=300)
    return p.returncode, p.stderr


@pytest.fixture(scope="session")
def small():
    # The Cornell box, small: every test renders it in well under a second
    # once the device's kernels are built.
    return wavepath.load(CORNELL, resolution=(32, 32), spp=4)


@pytest.fixture(scope="session")
def gpu_render(small):
    # Seed 3 on the default device (lavapipe in CI), shared by the tests that check against it.
    return wavepath.render(small, seed=3)
