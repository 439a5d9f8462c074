"""How pytest runs the chapters on both cores (conftest.py, pyproject's addopts): each chapter's
cells in one xdist worker, in order; the heaviest chapters queued first; the chapter lists named
in conftest.py are chapters of the toc."""

from __future__ import annotations

import importlib.util
import shlex
import tomllib
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[2]


def _conftest():
    spec = importlib.util.spec_from_file_location("root_conftest", ROOT / "conftest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_suite_runs_on_two_workers_with_each_chapter_in_one():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    options = shlex.split(config["tool"]["pytest"]["ini_options"]["addopts"])
    # loadfile (or loadscope: by module) keeps the cells of one chapter in one worker, in order;
    # `load` would spread a chapter's cells over two kernels.
    assert options[options.index("-n") + 1] in ("2", "auto")
    assert options[options.index("--dist") + 1] in ("loadfile", "loadscope")


def test_the_chapter_lists_name_chapters_of_the_toc():
    conftest = _conftest()
    chapters = set(conftest.book_chapters())
    assert set(conftest.HEAVY_FIRST) <= chapters
    assert set(conftest.SLOW_CHAPTERS) <= chapters


def test_the_heaviest_chapters_are_queued_first_each_in_its_order():
    conftest = _conftest()
    book = conftest.BOOK
    heavy, other = conftest.HEAVY_FIRST[0], conftest.HEAVY_FIRST[-1]
    items = [SimpleNamespace(path=ROOT / "tests" / "test_a.py", name="t1"),
             SimpleNamespace(path=book / "intro.md", name="Cell 0"),
             SimpleNamespace(path=book / f"{other}.md", name="Cell 0"),
             SimpleNamespace(path=book / f"{heavy}.md", name="Cell 0"),
             SimpleNamespace(path=book / f"{other}.md", name="Cell 1"),
             SimpleNamespace(path=book / f"{heavy}.md", name="Cell 1"),
             SimpleNamespace(path=ROOT / "tests" / "test_a.py", name="t2")]
    conftest.pytest_collection_modifyitems(None, items)
    assert [(Path(i.path).stem, i.name) for i in items] == [
        (heavy, "Cell 0"), (heavy, "Cell 1"), (other, "Cell 0"), (other, "Cell 1"),
        ("test_a", "t1"), ("intro", "Cell 0"), ("test_a", "t2")]
