"""Shared fixtures of the Python tests: the output folder, the command-line tool, a small synthetic scan."""
import os
import pathlib
import shutil

import pytest


def output_root() -> pathlib.Path:
    return pathlib.Path(os.environ.get("TM_TEST_OUTPUT_DIR", "/tmp/tissuemosaic-python-tests"))


@pytest.fixture(scope="session")
def out_dir() -> pathlib.Path:
    root = output_root()
    shutil.rmtree(root, ignore_errors=True)
    root.mkdir(parents=True)
    return root


@pytest.fixture(scope="session")
def cli() -> str:
    path = os.environ.get("TM_CLI", "")
    assert path and os.access(path, os.X_OK), "TM_CLI must name the built tissuemosaic tool (ctest sets it)"
    return path


@pytest.fixture(scope="session")
def with_gui() -> bool:
    return os.environ.get("TM_WITH_GUI", "ON").upper() in ("ON", "1", "TRUE", "YES")


@pytest.fixture(scope="session")
def small_scan(out_dir):
    """40 frames, 320x180: a few key frames and a model of some thousand points in a few seconds."""
    import tissuemosaic as tm
    return tm.synth.scan(out_dir / "scan", frames=40, width=320, height=180, seed=3)
