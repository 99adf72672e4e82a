"""Comments and docs cite what a reader of the repository can open: a page of docs/ (with
its section), a paper, an upstream issue. The product specification and the course material
the project started from are not in the repository, so "SPEC §N" and "seed 000"-style
citations are refused, and every `docs/PAGE.md#section` cited must exist."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SOURCES = ("wgpu_shading/**/*.py", "wgsl/**/*.wgsl", "tests/**/*.py", "tests/golden/**/*.toml", "benchmarks/**/*.py",
           "docs/*.md", "docs/*.py", "README.md")
UNREADABLE = re.compile(r"SPEC §|[Ss]eeds?(/| file | )0\d\d\b|\bfile 00\d\b")
DOC_LINK = re.compile(r"docs/([\w-]+\.md)#([\w-]+)")
# A link between pages of docs/ (`[text](page.md#section)`) or within one (`[text](#section)`).
RELATIVE_LINK = re.compile(r"\]\((?:([\w-]+\.md))?#([\w-]+)\)")


def _files():
    for pattern in SOURCES:
        yield from (p for p in sorted(ROOT.glob(pattern)) if p.is_file() and p.name != Path(__file__).name)


def _anchors(page: Path) -> set[str]:
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to hyphens."""
    headings = re.findall(r"^#+\s+(.*)$", page.read_text(encoding="utf-8"), flags=re.MULTILINE)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in headings}


def test_no_citation_a_reader_cannot_open():
    found = [
        f"{path.relative_to(ROOT)}:{number}: {line.strip()}"
        for path in _files()
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if UNREADABLE.search(line)
    ]
    assert not found, "cite docs/ (docs/conventions.md#where-the-rules-come-from), a paper or an issue instead:\n" + "\n".join(found)


def test_cited_doc_sections_exist():
    missing = []
    for path in _files():
        for page, anchor in DOC_LINK.findall(path.read_text(encoding="utf-8")):
            target = ROOT / "docs" / page
            if not target.exists() or anchor not in _anchors(target):
                missing.append(f"{path.relative_to(ROOT)}: docs/{page}#{anchor}")
    assert not missing, "cited sections that do not exist:\n" + "\n".join(sorted(set(missing)))


def test_links_between_doc_pages_exist():
    missing = []
    for page in sorted((ROOT / "docs").glob("*.md")):
        for target_name, anchor in RELATIVE_LINK.findall(page.read_text(encoding="utf-8")):
            target = page.parent / target_name if target_name else page
            if not target.exists() or anchor not in _anchors(target):
                missing.append(f"docs/{page.name}: {target_name}#{anchor}")
    assert not missing, "links to sections that do not exist:\n" + "\n".join(sorted(set(missing)))


def test_the_checks_are_not_vacuous():
    assert UNREADABLE.search("normals (SPEC §12)") and UNREADABLE.search("as in seed 000") and UNREADABLE.search("(file 000)")
    assert not UNREADABLE.search("seed000_grid_flat") and not UNREADABLE.search("random seed 0")
    assert "the-lighting-equation" in _anchors(ROOT / "docs" / "conventions.md")
    assert RELATIVE_LINK.findall("[a](#where-things-stand) [b](conventions.md#textures)") == [
        ("", "where-things-stand"), ("conventions.md", "textures")]
    assert "colour--depth-against-pyrender" in _anchors(ROOT / "docs" / "performance.md")
