"""Execute the notebooks in this folder (or those named) top to bottom, in memory: the stored
files keep no outputs. A failing cell (an assert against the reference) fails the run.

    python python/notebooks/execute.py [NOTEBOOK ...]

Sizes come from the environment (PSEUDORIGID_NB_N, PSEUDORIGID_NB_STEPS; small by default).
"""

from __future__ import annotations

import pathlib
import sys
import time

import nbformat
from nbclient import NotebookClient

HERE = pathlib.Path(__file__).resolve().parent


def main(names: list) -> int:
    paths = [pathlib.Path(n) for n in names] or sorted(HERE.glob("*.ipynb"))
    for path in paths:
        nb = nbformat.read(path, as_version=4)
        if any(c.get("outputs") or c.get("execution_count") for c in nb.cells if c.cell_type == "code"):
            print(f"{path.name}: stored with outputs (strip them)", file=sys.stderr)
            return 1
        start = time.perf_counter()
        client = NotebookClient(nb, timeout=900, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}})
        client.execute()
        print(f"{path.name}: {len(nb.cells)} cells executed in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
