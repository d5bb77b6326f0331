"""Runs an example script of Module/Python/examples and returns its JSON report."""
import json
import os
import pathlib
import subprocess
import sys

EXAMPLES = pathlib.Path(os.environ.get("TM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2])) / "Module" / "Python" / "examples"


def run_example(name, *arguments):
    completed = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, arguments)], capture_output=True,
                               text=True)
    assert completed.returncode == 0, f"{name} exited {completed.returncode}:\n{completed.stderr}"
    return json.loads(completed.stdout)


def example_module(name):
    """An example script imported as a module (its helpers, e.g. reconstruct_video.first_tum_pose)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
