"""Dump every glued value of the built book, to diff before and after a change.

Usage (after ``jupyter-book build book/``)::

    python .ci/glue_dump.py _build/jupyter_execute > glue.json
    python .ci/glue_dump.py --diff before.json after.json

myst-nb writes each chapter's glued values to ``_build/jupyter_execute/CHAPTER.glue.json``;
we record each value's text (Markdown, LaTeX or plain) per chapter; figures as ``<figure>``.
"""

from __future__ import annotations

import json
import re
import sys
from collections import Counter
from pathlib import Path

#: What counts as a number inside a glued text (after the minus sign U+2212 is read as "-": the
#: book typesets it, the number is the same).
NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def numbers(text: str) -> Counter:
    return Counter(NUMBER.findall(text.replace("\u2212", "-")))


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


def _by_key(values: dict[str, dict[str, str]]) -> dict[str, dict[str, str]]:
    """Key -> {chapter: text}: a value may move between chapters (e.g. into an appendix)."""
    out: dict[str, dict[str, str]] = {}
    for chapter, glued in values.items():
        for key, text in glued.items():
            out.setdefault(key, {})[chapter] = text
    return out


def diff(before: dict, after: dict) -> int:
    """Print every earlier key that is gone or whose numbers changed; return their count.

    Keys are matched across chapters. Text around the numbers (wording, layout) may change; the
    numbers in it, compared as a multiset of the strings that look like numbers, may not.
    """
    old, new = _by_key(before), _by_key(after)
    changed = 0
    for key in sorted(old):
        reference = next(iter(old[key].values()))
        if key not in new:
            changed += 1
            print(f"{key}: gone (was in {sorted(old[key])})")
            continue
        for chapter, text in sorted(new[key].items()):
            lost = numbers(reference) - numbers(text)
            if lost:
                changed += 1
                print(f"{chapter}:{key}: numbers {sorted(lost.elements())} changed: "
                      f"{reference[:80]!r} -> {text[:80]!r}")
    print(f"{changed} of {len(old)} earlier glued values gone or changed "
          f"({len(new)} keys now)")
    return changed


if __name__ == "__main__":
    if sys.argv[1] == "--diff":
        load = lambda p: json.loads(Path(p).read_text())  # noqa: E731
        sys.exit(1 if diff(load(sys.argv[2]), load(sys.argv[3])) else 0)
    json.dump(dump(Path(sys.argv[1])), sys.stdout, indent=1, sort_keys=True)
