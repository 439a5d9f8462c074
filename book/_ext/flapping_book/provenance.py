"""Where the book comes from: package version, git commit, and the size of each chapter.

The introduction glues the version and the commit, so that every built page names the code that
computed it; the status page (``book/status.md``) tabulates :func:`chapter_statistics` for every
chapter, beside myst-nb's table of execution times.

Nothing here runs at import time; git is called only by :func:`git_commit`, and a missing git (or a
source tree that is not a clone) gives a fallback string instead of an error.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

__all__ = ["ChapterStatistics", "chapter_statistics", "git_commit", "package_version"]

#: What :func:`git_commit` returns when the commit cannot be read.
UNKNOWN_COMMIT = "unknown (not a git checkout)"


def package_version() -> str:
    """The version of the installed ``flapping`` package (``flapping.__version__``)."""
    import flapping

    return str(flapping.__version__)


def git_commit(root: str | Path | None = None, *, timeout: float = 10.0) -> str:
    """The short hash of the checked-out commit, ``+ local changes`` if the work tree differs.

    Parameters
    ----------
    root : str or Path, optional
        A folder inside the repository; default: the package's own folder.
    timeout : float
        Seconds to wait for each git call.

    Returns
    -------
    str
        E.g. ``"e741e20"`` or ``"e741e20 + local changes"``; :data:`UNKNOWN_COMMIT` when git is
        missing or ``root`` is not inside a git work tree.
    """
    folder = Path(root) if root is not None else Path(__file__).resolve().parent

    def git(*args: str) -> str:
        done = subprocess.run(["git", "-C", str(folder), *args], capture_output=True, text=True,
                              timeout=timeout, check=True)
        return done.stdout.strip()

    try:
        commit = git("rev-parse", "--short", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return UNKNOWN_COMMIT
    return f"{commit} + local changes" if dirty else commit


@dataclass(frozen=True)
class ChapterStatistics:
    """The size of one MyST Markdown chapter, as a reader meets it.

    Attributes
    ----------
    words : int
        Words of prose (text, headings, admonitions, captions, table titles), without code cells,
        directive options, labels, comments, math and glue roles (a glued number counts as one
        word).
    figures : int
        ``glue:figure`` and ``figure`` directives.
    tables : int
        ``table`` directives (glued or written).
    code_cells : int
        ``code-cell`` blocks, hidden or not.
    glued : int
        Glue references (``{glue:text}``, ``{glue:md}``, ``{glue:math}`` ...) in the text.
    exercises : int
        ``exercise`` directives (plain or gated with ``exercise-start``).
    """

    words: int
    figures: int
    tables: int
    code_cells: int
    glued: int
    exercises: int


_FENCE = re.compile(r"^(`{3,}|:{3,})\s*(\{([^}]*)\})?(.*)$")
_GLUE_ROLE = re.compile(r"\{glue(?::\w+)?\}`[^`]*`")
_ROLE = re.compile(r"\{[\w:+-]+\}`([^`]*)`")
_MATH = re.compile(r"\$\$.*?\$\$|\$[^$\n]+\$", re.DOTALL)
_WORD = re.compile(r"[A-Za-z0-9][A-Za-z0-9'’\-]*")


def chapter_statistics(path: str | Path) -> ChapterStatistics:
    """Count the prose words, figures, tables, code cells and glued numbers of a chapter.

    Parameters
    ----------
    path : str or Path
        A MyST Markdown file (with or without jupytext front matter).

    Returns
    -------
    ChapterStatistics
    """
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    if lines and lines[0].strip() == "---":  # front matter
        end = next((k for k in range(1, len(lines)) if lines[k].strip() == "---"), 0)
        lines = lines[end + 1:]
    prose: list[str] = []
    counts = {"figures": 0, "tables": 0, "code_cells": 0, "exercises": 0}
    stack: list[tuple[str, str]] = []  # open fences: (marker, directive name)
    for line in lines:
        match = _FENCE.match(line.strip())
        if match and stack and match.group(1) == stack[-1][0] and not match.group(2) \
                and not match.group(4).strip():
            stack.pop()
            continue
        if match and (match.group(2) or not stack or stack[-1][1] not in ("code-cell", "code")):
            name = (match.group(3) or "code").strip()
            if name == "code-cell":
                counts["code_cells"] += 1
            elif name in ("glue:figure", "figure"):
                counts["figures"] += 1
            elif name in ("table", "captioned-exec-table"):  # the latter: book/status.md
                counts["tables"] += 1
            elif name in ("exercise", "exercise-start"):
                counts["exercises"] += 1
            if name.endswith(("-start", "-end")):
                continue   # gated directives (sphinx-exercise) are not closed by a fence
            stack.append((match.group(1), name))
            title = match.group(4).strip()
            if title and name not in ("code-cell", "code", "math") and not name.startswith("glue"):
                prose.append(title)
            continue
        if stack and stack[-1][1] in ("code-cell", "code", "math", "glue:md", "glue:math"):
            continue
        text = line.strip()
        if text.startswith((":", "(", "%", "<!--")) and not text.startswith(":::"):
            continue  # directive options, labels (label)=, comments
        prose.append(line)
    text = "\n".join(prose)
    glued = len(_GLUE_ROLE.findall(text))
    text = _GLUE_ROLE.sub(" 0 ", text)
    text = _MATH.sub(" ", text)
    text = _ROLE.sub(lambda m: " " + m.group(1) + " ", text)
    text = re.sub(r"```.*?```|`[^`]*`", " x ", text)
    return ChapterStatistics(words=len(_WORD.findall(text)), glued=glued, **counts)
