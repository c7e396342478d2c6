"""Runs a notebook headless on a Jupyter kernel (Debian's nbclient and
ipykernel) and fails on any cell's error; checks that the notebook is kept
in the repository without outputs.

Usage: run_notebook.py NOTEBOOK [KERNEL]
KERNEL is a registered kernel's name (python3 if left out: ipykernel's
kernel on this interpreter). Cells run in a scratch folder; matplotlib
draws into the notebook (no display needed).
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
    kernel = sys.argv[2] if len(sys.argv) > 2 else "python3"
    notebook = nbformat.read(path, as_version=4)
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type == "code" and (cell.outputs or cell.execution_count is not None):
            sys.exit(f"{path}: cell {index} holds outputs; strip them before committing")
    scratch = tempfile.mkdtemp(prefix="notebook_")
    try:
        client = NotebookClient(notebook, timeout=CELL_TIMEOUT_S, kernel_name=kernel,
                                resources={"metadata": {"path": scratch}})
        try:
            client.execute()
        except CellExecutionError as error:
            sys.exit(f"{path}: a cell failed:\n{error}")
        for cell in notebook.cells:
            for output in cell.get("outputs", []):
                if output.get("output_type") == "stream":
                    sys.stdout.write(output["text"])
        print(f"{path}: every cell ran on kernel {kernel}")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
