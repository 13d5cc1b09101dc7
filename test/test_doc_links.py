"""Docs state the present: every docs/ file is reached by links from a README, and every link of
the READMEs and the docs they reach points to a file that exists (scripts/check_doc_links)."""
import importlib.machinery
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def load_checker():
    loader = importlib.machinery.SourceFileLoader("check_doc_links",
                                                  str(ROOT / "scripts" / "check_doc_links"))
    spec = importlib.util.spec_from_loader("check_doc_links", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def workspace_check():
    """(unlinked, broken) of the workspace, checked once for the two tests below."""
    return load_checker().check(ROOT)


def test_every_docs_file_is_linked_from_a_readme(workspace_check):
    unlinked, _ = workspace_check
    assert unlinked == [], "docs/ files no README links to (link them or delete them)"


def test_every_link_points_to_a_file(workspace_check):
    _, broken = workspace_check
    assert broken == [], "links to missing files"


def test_checker_finds_an_unlinked_file_and_a_broken_link(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "linked.md").write_text("[plot](plot.png)\n")
    (tmp_path / "docs" / "plot.png").write_bytes(b"")
    (tmp_path / "docs" / "stale.md").write_text("old\n")
    (tmp_path / "README.md").write_text("[r](docs/linked.md) [gone](docs/gone.md)\n"
                                         "```\n[in code](docs/stale.md)\n```\n")
    unlinked, broken = load_checker().check(tmp_path)
    assert unlinked == ["docs/stale.md"]
    assert broken == ["README.md: docs/gone.md"]
