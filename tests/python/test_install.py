"""The installed module: cmake --install puts it in a site-packages layout."""

import os
import subprocess
import sys

import pytest

BUILD_DIR = os.environ.get("IPMC_SWIM_BUILD_DIR")
SITE = os.environ.get("IPMC_SWIM_PYTHON_INSTALL_DIR")
CMAKE = os.environ.get("IPMC_SWIM_CMAKE", "cmake")


@pytest.mark.skipif(not BUILD_DIR or not SITE, reason="needs the build tree (run by CTest)")
def test_the_installed_package_imports_from_the_prefixs_site_packages(tmp_path):
    prefix = tmp_path / "prefix"
    subprocess.run([CMAKE, "--install", BUILD_DIR, "--prefix", prefix], check=True,
                   capture_output=True)
    code = ("import ipmc_swim, os\n"
            "print(ipmc_swim.__file__)\n"
            "print(os.path.isfile(os.path.join(ipmc_swim.MODELS_DIR, 'flagellum3_clamped.xml')))\n"
            "print(len(ipmc_swim.bench(duration_s=0.05)['time_s']))\n")
    env = {"PATH": os.environ.get("PATH", ""), "PYTHONPATH": str(prefix / SITE)}
    # A sanitized build's module needs its runtime preloaded (tests/CMakeLists.txt).
    env.update({k: v for k, v in os.environ.items() if k in ("LD_PRELOAD", "ASAN_OPTIONS")})
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    module_file, has_models, samples = done.stdout.split()
    assert module_file.startswith(str(prefix / SITE / "ipmc_swim"))
    assert has_models == "True"
    assert samples == "50"
