"""Provenance: version, commit (with a fallback), and the size of a chapter."""

import flapping
from flapping_book.provenance import UNKNOWN_COMMIT, chapter_statistics, git_commit, package_version


def test_version_is_the_package_version():
    assert package_version() == flapping.__version__


def test_commit_outside_a_repository_falls_back(tmp_path):
    assert git_commit(tmp_path) == UNKNOWN_COMMIT


def test_chapter_statistics_count_prose_not_code(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "---\njupytext: {}\n---\n# A title here\n\nOne two three {glue:text}`x:.2f` four $a + b$.\n\n"
        "```{code-cell} ipython3\n:tags: [remove-cell]\nnot counted at all\n```\n\n"
        "```{glue:figure} fig\n:name: fig\n\nCaption words.\n```\n\n"
        "````{table} Table title\n:name: t\n\n```{glue:md} t\n:format: myst\n```\n````\n\n"
        "```{exercise}\nDo it.\n```\n", encoding="utf-8")
    stats = chapter_statistics(page)
    assert (stats.figures, stats.tables, stats.code_cells, stats.glued, stats.exercises) == (
        1, 1, 1, 1, 1)
    # A title here (3) + One two three 0 four (5) + Caption words (2) + Table title (2) + Do it (2)
    assert stats.words == 14


def test_the_captioned_execution_table_counts_as_a_table(tmp_path):
    page = tmp_path / "status.md"
    page.write_text("# Status\n\n```{captioned-exec-table} Execution of each page.\n"
                    ":name: tab-exec\n```\n", encoding="utf-8")
    stats = chapter_statistics(page)
    assert stats.tables == 1 and stats.words == 5   # Status + its caption's four words
