"""Release metadata agrees with itself: one version, one licence, in every file that states them."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import flapping

ROOT = Path(__file__).parents[1]


def _cff_field(name: str) -> str:
    match = re.search(rf"^{name}:\s*(.+)$", (ROOT / "CITATION.cff").read_text(), re.MULTILINE)
    assert match, f"CITATION.cff has no top-level {name}"
    return match.group(1).strip().strip('"')


def test_the_version_is_single_sourced():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" in pyproject["project"]["dynamic"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "flapping.__version__"}
    assert _cff_field("version") == flapping.__version__
    assert f"## [{flapping.__version__}]" in (ROOT / "CHANGELOG.md").read_text()
    # The book's helpers (book/_ext, a package of their own) are released with the package.
    helpers = tomllib.loads((ROOT / "book" / "_ext" / "pyproject.toml").read_text())
    assert helpers["project"]["version"] == flapping.__version__


def test_the_licence_is_the_same_everywhere():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    helpers = tomllib.loads((ROOT / "book" / "_ext" / "pyproject.toml").read_text())
    assert pyproject["project"]["license"] == "MIT" == _cff_field("license")
    assert helpers["project"]["license"] == "MIT"
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_the_package_declares_its_types():
    assert (Path(flapping.__file__).parent / "py.typed").exists()
