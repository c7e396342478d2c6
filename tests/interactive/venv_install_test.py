"""`pip install sim/python` into a fresh virtual environment, without the
network, gives a package that runs the default job as the command line
does, bit for bit, and refuses to load a mismatched extension or library.

Usage: venv_install_test.py SOURCE_DIR BUILD_DIR IPMC_SWIM
(CTest, tests/interactive/CMakeLists.txt: the build tree is up to date, so
the package's build only runs `cmake --install` into its staging folder.)
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

SOURCE_DIR, BUILD_DIR, PROGRAM = sys.argv[1:4]

# In the venv: the package's own scenario (it carries the models and
# scenarios), one cycle, written to OUT; prints the per-cycle swim.
RUN_IN_VENV = """
import json, os, sys
import ipmc_swim
assert ipmc_swim.__file__.startswith(sys.prefix), ipmc_swim.__file__
r = ipmc_swim.run(os.path.join(ipmc_swim.SCENARIOS_DIR, "paper.toml"), cycles=1, out=sys.argv[1])
print(json.dumps({"version": ipmc_swim.__version__,
                  "com_along_mm": r.cycles["com_along_mm"].tolist()}))
"""


# A one-cell notebook on the venv's kernel, printing where the package is.
KERNEL_IMPORT = """
import nbformat
from nbclient import NotebookClient
nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(
    "import ipmc_swim; print(ipmc_swim.__file__)")])
NotebookClient(nb, timeout=120, kernel_name="ipmc-venv").execute()
print(nb.cells[0].outputs[0]["text"].strip())
"""


def run(command, **kwargs):
    done = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if done.returncode != 0:
        sys.exit(f"FAILED: {' '.join(map(str, command))}\n{done.stdout}\n{done.stderr}")
    return done.stdout


def import_error(python):
    done = subprocess.run([python, "-c", "import ipmc_swim"], capture_output=True, text=True,
                          cwd=tempfile.gettempdir())
    assert done.returncode != 0, "a mismatched package imported"
    return done.stderr.strip().splitlines()[-1]


def main():
    scratch = tempfile.mkdtemp(prefix="venv_install_")
    try:
        venv = os.path.join(scratch, "venv")
        # --without-pip: Debian's pip, seen through the system site packages,
        # installs into the venv as the venv's own would (which takes 13 s to
        # set up on a loaded machine).
        run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", "--without-pip", venv])
        python = os.path.join(venv, "bin", "python")
        # No index, no build isolation: Debian's setuptools builds it, and
        # pip cannot reach the network.
        env = dict(os.environ, IPMC_SWIM_BUILD_DIR=BUILD_DIR, PIP_NO_INDEX="1",
                   PIP_DISABLE_PIP_VERSION_CHECK="1")
        run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index",
             os.path.join(SOURCE_DIR, "sim", "python")], env=env, cwd=scratch)

        from_python = os.path.join(scratch, "python_run")
        result = json.loads(run([python, "-c", RUN_IN_VENV, from_python], cwd=scratch))
        from_cli = os.path.join(scratch, "cli_run")
        run([PROGRAM, "run", os.path.join(SOURCE_DIR, "scenarios", "paper.toml"), "--cycles", "1",
             "--out", from_cli], cwd=scratch)
        for name in ("timeseries.csv", "states.csv"):
            with open(os.path.join(from_python, name), "rb") as a, \
                    open(os.path.join(from_cli, name), "rb") as b:
                assert a.read() == b.read(), f"{name} differs between the venv's module and the CLI"
        with open(os.path.join(from_cli, "summary.json")) as f:
            summary = json.load(f)
        cli_swim = [cycle["com_along_mm"] for cycle in summary["per_cycle"]]
        assert result["com_along_mm"] == cli_swim, (result, cli_swim)
        version = run([PROGRAM, "--version"]).split()[-1]
        assert result["version"] == version, (result["version"], version)

        # A Jupyter kernel of the venv, registered as docs/PYTHON.md says,
        # imports the venv's package, and the first-study notebook runs on
        # it, every cell (docs/notebooks).
        # (ipykernel leaves its scratch copy of the spec in TMPDIR.)
        run([python, "-m", "ipykernel", "install", "--prefix", venv, "--name", "ipmc-venv"],
            cwd=scratch, env=dict(os.environ, TMPDIR=scratch))
        kernel = run([python, "-c", KERNEL_IMPORT], cwd=scratch,
                     env=dict(os.environ, PYDEVD_DISABLE_FILE_VALIDATION="1"))
        assert kernel.strip().startswith(os.path.join(venv, "lib")), kernel
        notebook = os.path.join(SOURCE_DIR, "docs", "notebooks", "first_study.ipynb")
        print(run([python, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                        "run_notebook.py"), notebook, "ipmc-venv"],
                  cwd=scratch, env=dict(os.environ, PYDEVD_DISABLE_FILE_VALIDATION="1")),
              end="")

        # A package whose files disagree: its Python part against its
        # extension, then the extension against the library it loads.
        package = os.path.join(venv, "lib", f"python{sys.version_info[0]}.{sys.version_info[1]}",
                               "site-packages", "ipmc_swim")
        paths = os.path.join(package, "_paths.py")
        text = open(paths).read()
        with open(paths, "w") as f:
            f.write(text.replace(f'VERSION = "{version}"', 'VERSION = "0.0.1"'))
        message = import_error(python)
        assert re.search(r"ImportError: ipmc_swim: the package .* is version 0\.0\.1 but its "
                         rf"extension ipmc_swim._core is {re.escape(version)}", message), message
        with open(paths, "w") as f:
            f.write(text)
        library = os.path.join(package, "libipmc_swim.so.0")
        binary = open(library, "rb").read()
        marker = b"\0" + version.encode() + b"\0"
        assert binary.count(marker) == 1, "the library's version string is not found once"
        other = "9" * len(version)
        with open(library, "wb") as f:
            f.write(binary.replace(marker, b"\0" + other.encode() + b"\0"))
        message = import_error(python)
        assert (f"ImportError: ipmc_swim: the module ipmc_swim._core is version {version} but the "
                f"library libipmc_swim it loaded is {other}") in message, message
        print(f"venv install: {result['com_along_mm']} mm, as the command line; "
              "mismatched versions refused")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
