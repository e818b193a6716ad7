"""Builds the frnn Python package: CMake compiles the module (frnn._frnn), setuptools packs it
with python/frnn/*. Run through pip (docs/PYTHON.md), not directly.

Only the core library and the module are configured: no tests, tools, simulation, Vulkan or MPI.
The version comes from one place, CMakeLists.txt's project(frnn VERSION ...).
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def cmake_project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    found = re.search(r"project\(\s*frnn\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if not found:
        raise RuntimeError(f"{ROOT / 'CMakeLists.txt'}: no 'project(frnn VERSION x.y.z)'")
    return found.group(1)


class CMakeModule(Extension):
    """The pybind11 module that CMake's target frnn_python builds."""

    def __init__(self, name):
        super().__init__(name, sources=[])


class BuildWithCMake(build_ext):
    def build_extension(self, ext):
        tree = Path(self.build_temp).resolve() / "cmake"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(tree),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DFRNN_BUILD_PYTHON=ON",
            "-DFRNN_BUILD_TESTS=OFF", "-DFRNN_BUILD_APPS=OFF", "-DFRNN_BUILD_BENCHMARKS=OFF",
            "-DFRNN_BUILD_SIM=OFF", "-DFRNN_BUILD_VULKAN=OFF", "-DFRNN_BUILD_MPI=OFF",
            "-DFRNN_INSTALL=OFF",
            # The interpreter pip runs: a venv's python builds for that venv.
            f"-DPython3_EXECUTABLE={sys.executable}",
        ]
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(tree), "--target", "frnn_python", "-j", jobs],
                       check=True)

        suffix = Path(self.get_ext_filename("_frnn")).name
        built = tree / "python" / "frnn" / suffix
        if not built.is_file():
            raise RuntimeError(f"CMake built no {built}: the module's suffix should be {suffix}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(
    version=cmake_project_version(),
    packages=["frnn"],
    package_dir={"frnn": "python/frnn"},
    package_data={"frnn": ["__init__.pyi", "py.typed"]},
    ext_modules=[CMakeModule("frnn._frnn")],
    cmdclass={"build_ext": BuildWithCMake},
    zip_safe=False,
)
