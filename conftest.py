"""Run the book's chapters as tests: `python -m pytest` executes every chapter listed in
book/_toc.yml with nbval, beside the unit tests in tests/.

Chapters are MyST Markdown notebooks (book/NAME.md with jupytext front matter). For each chapter
in the toc (except the bibliography page) this hook:

1. converts the .md to an .ipynb with jupytext, written under pytest's cache directory
   (.pytest_cache/, git-ignored), never beside the chapter;
2. hands that notebook to nbval in lax mode: every code cell runs in order in one fresh kernel of
   the Python running pytest, an exception fails that cell's test, and outputs are not compared
   (none are stored); cells tagged ``raises-exception`` may raise, as in the book build;
3. starts the kernel in book/, as the Jupyter Book build does, so relative paths behave the same.

The suite runs on both cores with pytest-xdist (``-n 2 --dist loadfile`` in pyproject's addopts):
``loadfile`` hands all the cells of one chapter to one worker, which runs them in order in the
chapter's one kernel, as without xdist. The heaviest chapters are queued first, so that the last
chapter a worker starts is a short one and the two cores finish together.

Test IDs name the chapter, e.g. ``book/intro.md::Cell 0``. A chapter listed in the toc whose file
does not exist yet is reported as skipped (``book/_toc.yml::NAME``); the book build fails on it.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import jupytext
import nbformat
import pytest
import yaml
from nbval.kernel import CURRENT_ENV_KERNEL_NAME, RunningKernel
from nbval.plugin import IPyNbFile

BOOK = Path(__file__).parent / "book"
TOC = BOOK / "_toc.yml"
NOT_EXECUTED = {"references"}  # pages with no code: only the bibliography directive
#: Chapters with a cell over 20 s (CI: each of the two workers has a core, so a cell's CPU time
#: is about its wall time): every cell of such a chapter is marked `slow` too, since a chapter's
#: cells run in order in one kernel. Measured 2026-12-06, CPU time of each cell: the six-dof
#: lateral chapter's table of every preset takes 21 s (until the compiled six-dof path; drop
#: it then if no cell stays over 20 s); every other chapter's largest cell is
#: under 20 s (atlas 16 s, continuation 14 s, control 9 s since its windows are stored).
SLOW_CHAPTERS = {"lateral_stability"}
#: The chapters with the longest execution, longest first (CPU time measured 2026-12-06:
#: continuation 38 s, atlas 30 s, control 21 s, appendix_robustness 15 s; lateral_stability
#: 62 s on the six-dof paths of 2026-12-06), queued first (see pytest_collection_modifyitems).
HEAVY_FIRST = ("lateral_stability", "continuation", "atlas", "control", "appendix_robustness")


def _toc_entries(toc: dict) -> list[str]:
    """Every `file:` (and the root) of a jb-book toc, in reading order, without extension."""
    entries = [toc["root"]]

    def walk(node):
        if isinstance(node, dict):
            if "file" in node:
                entries.append(node["file"])
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk({k: v for k, v in toc.items() if k != "root"})
    return [str(Path(e).with_suffix("")) for e in entries]


def book_chapters() -> list[str]:
    """Chapter names (paths relative to book/, no extension) that pytest executes."""
    toc = yaml.safe_load(TOC.read_text(encoding="utf-8"))
    return [name for name in _toc_entries(toc) if name not in NOT_EXECUTED]


class MystChapter(IPyNbFile):
    """nbval's notebook collector, reading a MyST Markdown chapter through jupytext."""

    _read_from: Path | None = None

    @property
    def fspath(self):
        # nbval's collect() reads the notebook from str(self.fspath): during collection that is
        # the converted .ipynb; everywhere else it is the chapter, so test IDs name the chapter.
        return self._read_from if self._read_from is not None else self.path

    def collect(self):
        notebook = jupytext.read(self.path)
        name = self.path.relative_to(BOOK).with_suffix("").as_posix().replace("/", "--")
        ipynb = _notebook_dir(self.config) / f"{name}.ipynb"
        _write_atomically(notebook, ipynb)
        self.compare_outputs = False  # lax: outputs are never compared (none are stored)
        self._read_from = ipynb
        try:
            for item in super().collect():
                item.add_marker(pytest.mark.book)  # `-m "not book"` runs the unit tests alone
                if name in SLOW_CHAPTERS:
                    item.add_marker(pytest.mark.slow)
                yield item
        finally:
            self._read_from = None

    def setup(self):
        # Same interpreter as pytest (not whatever `python3` kernelspec is on the PATH), run from
        # book/ like the Jupyter Book build.
        self.kernel = RunningKernel(
            CURRENT_ENV_KERNEL_NAME,
            cwd=str(BOOK),
            startup_timeout=self.config.option.nbval_kernel_startup_timeout,
        )
        self.setup_sanitize_files()


class MissingChapter(pytest.Item):
    """A toc entry whose chapter file has not been written yet."""

    def runtest(self):
        pytest.skip(f"listed in book/_toc.yml but book/{self.name}.md does not exist yet")

    def reportinfo(self):
        return self.path, None, f"book/_toc.yml::{self.name}"


class TocFile(pytest.File):
    def collect(self):
        for name in book_chapters():
            if not (BOOK / f"{name}.md").exists():
                item = MissingChapter.from_parent(self, name=name)
                item.add_marker(pytest.mark.book)
                yield item


def _write_atomically(notebook, path: Path) -> None:
    # Under xdist every worker collects every chapter into the same cache directory: a reader
    # must never see another worker's half-written notebook.
    partial = path.with_name(f"{path.name}.{os.getpid()}.part")
    nbformat.write(notebook, partial)
    os.replace(partial, path)


def pytest_collection_modifyitems(config, items):
    """The heaviest chapters first (their cells kept together, in order), then the rest as
    collected: xdist's ``loadfile`` queues files in this order."""
    def rank(item):
        chapter = Path(str(item.path)).stem if Path(str(item.path)).is_relative_to(BOOK) else ""
        return HEAVY_FIRST.index(chapter) if chapter in HEAVY_FIRST else len(HEAVY_FIRST)

    items[:] = sorted(items, key=rank)  # sorted() is stable: the order within a rank is kept


def _notebook_dir(config) -> Path:
    cache = getattr(config, "cache", None)
    if cache is not None:
        return cache.mkdir("book-notebooks")
    return Path(tempfile.mkdtemp(prefix="book-notebooks-"))


def pytest_collect_file(file_path: Path, parent):
    if file_path == TOC:
        return TocFile.from_parent(parent, path=file_path)
    if (file_path.suffix == ".md" and file_path.is_relative_to(BOOK)
            and file_path.relative_to(BOOK).with_suffix("").as_posix() in book_chapters()):
        return MystChapter.from_parent(parent, path=file_path)
    return None
