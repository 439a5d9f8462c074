"""Dump every glued value of the built book, to diff before and after a change.

Usage (after ``jupyter-book build book/``)::

    python .ci/glue_dump.py _build/jupyter_execute > glue.json
    python .ci/glue_dump.py --diff before.json after.json

myst-nb writes each chapter's glued values to ``_build/jupyter_execute/CHAPTER.glue.json``;
we record each value's text (Markdown, LaTeX or plain) per chapter; figures as ``<figure>``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def dump(folder: Path) -> dict[str, dict[str, str]]:
    values: dict[str, dict[str, str]] = {}
    for path in sorted(folder.rglob("*.glue.json")):
        chapter = values.setdefault(path.name.removesuffix(".glue.json"), {})
        for name, out in json.loads(path.read_text()).items():
            data = {k.removeprefix("application/papermill.record/"): v
                    for k, v in out.get("data", {}).items()}
            text = next((data[k] for k in ("text/markdown", "text/latex", "text/plain")
                         if k in data), None)
            if any(k.startswith("image/") for k in data):
                text = "<figure>"
            chapter[name] = "".join(text) if isinstance(text, list) else str(text)
    return values


def diff(before: dict, after: dict) -> int:
    changed = 0
    for chapter in sorted(set(before) | set(after)):
        b, a = before.get(chapter, {}), after.get(chapter, {})
        for key in sorted(set(b) | set(a)):
            if b.get(key) != a.get(key):
                changed += 1
                print(f"{chapter}:{key}: {b.get(key)!r} -> {a.get(key)!r}")
    total = sum(len(v) for v in before.values())
    print(f"{changed} of {total} glued values changed")
    return changed


if __name__ == "__main__":
    if sys.argv[1] == "--diff":
        load = lambda p: json.loads(Path(p).read_text())  # noqa: E731
        sys.exit(1 if diff(load(sys.argv[2]), load(sys.argv[3])) else 0)
    json.dump(dump(Path(sys.argv[1])), sys.stdout, indent=1, sort_keys=True)
