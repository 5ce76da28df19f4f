"""pip install . — builds the voroclip Python package (python/voroclip) with its compiled core
voroclip._core through the project's CMake target (VOROCLIP_BUILD_PYTHON), offline, from
Debian's packages: cmake, a C++17 compiler, pybind11-dev, libeigen3-dev, libtbb-dev,
liblbfgspp-dev, zlib1g-dev, python3-dev, python3-numpy (scripts/setup.sh installs them).

    /usr/bin/python3 -m pip install --no-build-isolation .          # in a venv made with
                                                                    # --system-site-packages
    /usr/bin/python3 -m pip install --no-build-isolation --user --break-system-packages .

--no-build-isolation: pip would otherwise try to download setuptools and pybind11 from PyPI
into a fresh environment; here they come from Debian. CMAKE_BUILD_PARALLEL_LEVEL sets the
build's jobs (default 2).
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).parent.resolve()


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(voroclip VERSION (\d+\.\d+\.\d+)", text).group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        subprocess.check_call([
            "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
            "-DVOROCLIP_BUILD_PYTHON=ON", "-DVOROCLIP_BUILD_APPS=OFF",
            "-DVOROCLIP_BUILD_TESTS=OFF", "-DVOROCLIP_BUILD_BENCH=OFF",
            f"-DPython_EXECUTABLE={sys.executable}",
        ])
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2")
        subprocess.check_call(["cmake", "--build", str(build), "--target", "voroclip_python",
                               "-j", jobs])
        built = sorted((build / "python" / "voroclip").glob("_core*.so"))
        if not built:
            raise RuntimeError(f"the build left no _core*.so in {build / 'python' / 'voroclip'}")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    name="voroclip",
    version=version(),
    description="Exact clipped Voronoi diagrams, CVT and CVT meshing in 2D and 3D",
    long_description=(ROOT / "README.md").read_text(encoding="utf-8"),
    long_description_content_type="text/markdown",
    license="MIT",
    packages=["voroclip"],
    package_dir={"": "python"},
    package_data={"voroclip": ["*.pyi", "py.typed"]},
    ext_modules=[CMakeExtension("voroclip._core")],
    cmdclass={"build_ext": CMakeBuild},
    install_requires=["numpy"],
    python_requires=">=3.9",
    zip_safe=False,
)
