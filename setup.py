"""Building the locus Python package with CMake from pip (see pyproject.toml).

setuptools knows the package (python/locus/: the pure-Python part, the
type stubs, py.typed); the extension locus._locus is built by the project's
CMake (target locus_python, Release, the interpreter running pip), then
copied where setuptools packs it. Environment:
  LOCUS_CMAKE_BUILD_DIR  a CMake build tree to use (e.g. an existing build/;
                         default: one under setuptools' build_temp)
  LOCUS_CMAKE_ARGS       extra configure arguments (space-separated)
  LOCUS_BUILD_JOBS       parallel build jobs (default 2)
"""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(locus VERSION ([0-9.]+)", text).group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = pathlib.Path(os.environ.get("LOCUS_CMAKE_BUILD_DIR") or
                             pathlib.Path(self.build_temp).resolve() / "cmake")
        configure = ["cmake", "-S", str(ROOT), "-B", str(build)]
        if not (build / "CMakeCache.txt").exists():  # a new tree: only what the module needs, for this Python
            configure += ["-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={sys.executable}",
                          "-DLOCUS_BUILD_PYTHON=ON", "-DLOCUS_BUILD_TESTS=OFF", "-DLOCUS_BUILD_TOOLS=OFF"]
        configure += shlex.split(os.environ.get("LOCUS_CMAKE_ARGS", ""))
        subprocess.check_call(configure)
        subprocess.check_call(["cmake", "--build", str(build), "--target", "locus_python",
                               "-j", os.environ.get("LOCUS_BUILD_JOBS", "2")])
        suffix = target.name[len("_locus"):]
        built = build / "python" / "locus" / ("_locus" + suffix)
        if not built.exists():
            raise RuntimeError(f"CMake built no {built.name} in {built.parent} (another Python than "
                               f"{sys.executable}? set LOCUS_CMAKE_BUILD_DIR to a fresh folder)")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)


setup(
    version=version(),
    packages=["locus"],
    package_dir={"locus": "python/locus"},
    package_data={"locus": ["py.typed", "*.pyi"]},
    ext_modules=[CMakeExtension("locus._locus")],
    cmdclass={"build_ext": CMakeBuild},
    # Not build/: that is the CMake build tree of the README's commands.
    options={"build": {"build_base": "build-python"}},
    zip_safe=False,
)
