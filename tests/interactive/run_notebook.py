"""Runs a notebook headless on a Jupyter kernel (Debian's nbclient and
ipykernel) and fails on any cell's error; checks that the notebook is kept
in the repository without outputs.

Usage: run_notebook.py NOTEBOOK [--kernel-python]
The kernel is this interpreter's (ipykernel's python3 kernel runs
sys.executable), so running this script with a virtual environment's
python runs the notebook on that environment. Cells run in a scratch
folder; matplotlib draws into the notebook (no display needed).
"""
import os
import shutil
import sys
import tempfile

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

CELL_TIMEOUT_S = 600


def main():
    path = sys.argv[1]
    notebook = nbformat.read(path, as_version=4)
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type == "code" and (cell.outputs or cell.execution_count is not None):
            sys.exit(f"{path}: cell {index} holds outputs; strip them before committing")
    scratch = tempfile.mkdtemp(prefix="notebook_")
    try:
        client = NotebookClient(notebook, timeout=CELL_TIMEOUT_S, kernel_name="python3",
                                resources={"metadata": {"path": scratch}})
        try:
            client.execute()
        except CellExecutionError as error:
            sys.exit(f"{path}: a cell failed:\n{error}")
        for cell in notebook.cells:
            for output in cell.get("outputs", []):
                if output.get("output_type") == "stream":
                    sys.stdout.write(output["text"])
        print(f"{path}: every cell ran")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
