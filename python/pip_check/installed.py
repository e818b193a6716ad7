"""Checks the frnn that pip installed into a venv (argv[1]) and the wheel it made (argv[2]):
the module comes from the venv, its version is the package's, and a query agrees with cKDTree."""
import importlib.metadata
import sys
import zipfile
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

import frnn

venv, dist = Path(sys.argv[1]).resolve(), Path(sys.argv[2])

module_file = Path(frnn._frnn.__file__).resolve()
assert venv in module_file.parents, f"frnn imported from {module_file}, not from {venv}"
installed = importlib.metadata.version("frnn")
assert installed == frnn.__version__, f"metadata {installed} != frnn.__version__ {frnn.__version__}"

points = np.random.default_rng(7).random((5000, 3))
radius = 0.06
expected = cKDTree(points).query_pairs(radius, output_type="ndarray")
expected = expected[np.lexsort((expected[:, 1], expected[:, 0]))]
found = frnn.Grid(points, radius).query_pairs()
assert len(expected) > 1000, len(expected)
assert np.array_equal(found, expected), f"{len(found)} pairs, cKDTree {len(expected)}"

wheels = list(dist.glob("frnn-*.whl"))
assert len(wheels) == 1, wheels
with zipfile.ZipFile(wheels[0]) as wheel:
    names = wheel.namelist()
for wanted in ("frnn/__init__.py", "frnn/__init__.pyi", "frnn/py.typed"):
    assert wanted in names, f"{wheels[0].name} lacks {wanted}"
assert any(n.startswith("frnn/_frnn") and n.endswith(".so") for n in names), names
dist_info = f"frnn-{frnn.__version__}.dist-info"
assert f"{dist_info}/METADATA" in names, names
assert any(n.startswith(dist_info) and n.endswith("/LICENSE") for n in names), f"no LICENSE in {names}"
with zipfile.ZipFile(wheels[0]) as wheel:
    metadata = wheel.read(f"{dist_info}/METADATA").decode()
assert "License: MIT" in metadata.splitlines(), metadata

print(f"frnn {frnn.__version__} from {module_file}: {len(found)} pairs as cKDTree; "
      f"wheel {wheels[0].name}")
