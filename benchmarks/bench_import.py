"""Benchmark: what ``import flapping`` costs, against ``import numpy, scipy``.

In one run, on this machine, each command in a fresh interpreter (``python -c ...``), best of N:

1. ``import numpy, scipy``: the floor any scientific package starts from;
2. ``import flapping``: the package alone (issue 26 asks <= 2x the floor);
3. ``import flapping; flapping.find_hover_orbit``: the hover layer's first use, which the lazy
   namespace defers from 2 to here (printed for information, no target).

The ratios are wall times of whole processes, interpreter start-up included, as a user waits
for them. Run: ``python benchmarks/bench_import.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from _timing import best_of  # noqa: E402

TARGET = 2.0  # import flapping / import numpy, scipy (issue 26)
COMMANDS = {
    "numpy, scipy": "import numpy, scipy",
    "flapping": "import flapping",
    "flapping + hover layer": "import flapping; flapping.find_hover_orbit",
}


def _fresh(code: str) -> None:
    subprocess.run([sys.executable, "-c", code], check=True)


def main(repeat: int = 7) -> dict:
    times = {name: best_of(lambda code=code: _fresh(code), repeat)[0]
             for name, code in COMMANDS.items()}
    floor = times["numpy, scipy"]
    print(f"import time in a fresh interpreter (best of {repeat})")
    for name, seconds in times.items():
        print(f"  import {name:<24}: {seconds * 1e3:7.0f} ms   {seconds / floor:5.2f}x numpy+scipy")
    ratio = times["flapping"] / floor
    print(f"  ratio flapping/(numpy, scipy): {ratio:.2f} (target <= {TARGET:.0f}x: "
          f"{'met' if ratio <= TARGET else 'NOT met'})")
    return {"numpy_scipy_s": floor, "flapping_s": times["flapping"],
            "hover_s": times["flapping + hover layer"], "ratio": ratio}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="fresh interpreters per command")
    main(parser.parse_args().repeat)
