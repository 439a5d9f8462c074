"""Check that a built wheel holds everything the package needs, and print its size and contents.

Usage: ``python .ci/check_wheel.py dist/flapping-X.Y.Z-py3-none-any.whl``.
"""

from __future__ import annotations

import sys
import zipfile
from pathlib import Path

REQUIRED = [
    "flapping/__init__.py",
    "flapping/__main__.py",
    "flapping/cli.py",
    "flapping/hover/__init__.py",
    "flapping/studies/__init__.py",
    "flapping/py.typed",
    "flapping/model/__init__.py",
    "flapping/model/_derivatives_generated.py",
    "flapping/periodic/__init__.py",
    "flapping/book/__init__.py",
]

if __name__ == "__main__":
    wheel = Path(sys.argv[1])
    names = zipfile.ZipFile(wheel).namelist()
    missing = [name for name in REQUIRED if name not in names]
    missing += [] if any(n.endswith(".dist-info/licenses/LICENSE") or n.endswith("/LICENSE")
                         for n in names) else ["LICENSE"]
    source = sorted(p.relative_to(Path(__file__).parents[1]).as_posix()
                    for p in (Path(__file__).parents[1] / "flapping").rglob("*.py"))
    missing += [name for name in source if name not in names]
    print(f"{wheel.name}: {wheel.stat().st_size / 1024:.0f} KiB, {len(names)} files")
    for name in names:
        print("   ", name)
    if missing:
        sys.exit(f"missing from the wheel: {missing}")
