"""Builds the package ipmc_swim for pip with the project's CMake.

The package is the one `cmake --install` installs (sim/python/CMakeLists.txt:
ipmc_swim/__init__.py, the extension _core and _paths.py), with the shared
libraries it links (libipmc_swim, libipmc_linear; the extension looks for
them beside itself too) and the models and scenarios (_paths.py finds them
inside the package) copied into it, so the package works wherever pip puts
it. The build tree is IPMC_SWIM_BUILD_DIR, else the source tree's build/
(as ./run.sh and ./test.sh make it); it is configured if it is not yet, and
only the module's target is built in it. Nothing is downloaded.
"""

import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

SOURCE_DIR = Path(__file__).resolve().parent.parent.parent
BUILD_DIR = Path(os.environ.get("IPMC_SWIM_BUILD_DIR") or SOURCE_DIR / "build").resolve()
# setuptools' own scratch (build/, *.egg-info) goes into the CMake build
# tree, not into the source tree.
SCRATCH_DIR = BUILD_DIR / "sim" / "python" / "pip"
PACKAGE = "ipmc_swim"


def project_version():
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    return re.search(r"project\(ipmc_swim VERSION ([0-9.]+)", text).group(1)


def cache_value(build_dir, name):
    for line in (build_dir / "CMakeCache.txt").read_text().splitlines():
        if line.startswith(name + ":"):
            return line.split("=", 1)[1]
    return None


def fail(message):
    sys.exit(f"ipmc_swim setup: {message}")


class BuildWithCMake(build_py):
    """build_py that takes the package from the project's CMake install."""

    def run(self):
        cmake = os.environ.get("CMAKE", "cmake")
        build_dir = BUILD_DIR
        if not (build_dir / "CMakeCache.txt").is_file():
            subprocess.run([cmake, "-S", str(SOURCE_DIR), "-B", str(build_dir),
                            "-DCMAKE_BUILD_TYPE=Release",
                            f"-DPython3_EXECUTABLE={os.path.realpath(sys.executable)}"],
                           check=True)
        if cache_value(build_dir, "IPMC_SWIM_BUILD_PYTHON") == "OFF":
            fail(f"{build_dir} is configured with -DIPMC_SWIM_BUILD_PYTHON=OFF")
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run([cmake, "--build", str(build_dir), "--target", "ipmc_swim_python",
                        "-j", jobs], check=True)
        stage = Path(self.get_finalized_command("build").build_temp).resolve() / "cmake_install"
        shutil.rmtree(stage, ignore_errors=True)
        subprocess.run([cmake, "--install", str(build_dir), "--prefix", str(stage)], check=True,
                       stdout=subprocess.DEVNULL)
        self.assemble(stage, build_dir, Path(self.build_lib) / PACKAGE)

    @staticmethod
    def assemble(stage, build_dir, package):
        installed = stage / cache_value(build_dir, "IPMC_SWIM_PYTHON_INSTALL_DIR") / PACKAGE
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        if not (installed / f"_core{suffix}").is_file():
            built = sorted(p.name for p in installed.glob("_core*"))
            fail(f"{build_dir} built the module for another Python ({', '.join(built)}, "
                 f"this one needs _core{suffix}); set IPMC_SWIM_BUILD_DIR to a new folder "
                 "to build it for this Python")
        shutil.rmtree(package, ignore_errors=True)
        shutil.copytree(installed, package)
        libdir = stage / cache_value(build_dir, "CMAKE_INSTALL_LIBDIR")
        # Each library under its soname (libipmc_swim.so.0), the name the
        # extension asks the loader for.
        for library in ("libipmc_swim.so.*", "libipmc_linear.so.*"):
            for path in libdir.glob(library):
                if re.fullmatch(r"lib\w+\.so\.\d+", path.name):
                    shutil.copy2(path, package / path.name)
        # GNUInstallDirs leaves DATADIR empty in the cache for DATAROOTDIR.
        datadir = (cache_value(build_dir, "CMAKE_INSTALL_DATADIR")
                   or cache_value(build_dir, "CMAKE_INSTALL_DATAROOTDIR"))
        data = stage / datadir / "ipmc_swim"
        for folder in ("models", "scenarios"):
            shutil.copytree(data / folder, package / folder)


class PlatformDistribution(Distribution):
    """The extension is built by CMake, not setuptools: the wheel is for
    this platform and Python all the same."""

    def has_ext_modules(self):
        return True


SCRATCH_DIR.mkdir(parents=True, exist_ok=True)
setup(
    version=project_version(),
    options={"build": {"build_base": str(SCRATCH_DIR / "build")},
             "egg_info": {"egg_base": str(SCRATCH_DIR)}},
    packages=[PACKAGE],
    package_dir={PACKAGE: "ipmc_swim"},
    cmdclass={"build_py": BuildWithCMake},
    distclass=PlatformDistribution,
    zip_safe=False,
)
