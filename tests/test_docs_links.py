"""Every relative link of the README and the docs points at a file of this repository
and, where it names a section (``page.md#section``), at a heading that page has, with
the anchor GitHub derives from the heading's text."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
LINK = re.compile(r"\]\(([^)\s]+)\)")


def heading_anchors(markdown: str) -> set[str]:
    """The anchors of ``markdown``'s headings as GitHub makes them: lower case, every
    character but letters, digits, ``_``, ``-`` and spaces dropped, spaces turned into
    ``-``; a repeated anchor gets ``-1``, ``-2``, ... Headings in code blocks are not
    headings."""
    anchors: set[str] = set()
    seen: dict[str, int] = {}
    in_code = False
    for line in markdown.splitlines():
        if line.startswith("```"):
            in_code = not in_code
        match = None if in_code else re.match(r"#{1,6} (.*)", line)
        if match is None:
            continue
        anchor = re.sub(r"[^\w\- ]", "", match.group(1).strip().lower()).replace(" ", "-")
        count = seen.get(anchor, 0)
        seen[anchor] = count + 1
        anchors.add(anchor if count == 0 else f"{anchor}-{count}")
    return anchors


def broken_links(page: Path) -> list[str]:
    """``page``'s relative links whose file or section does not exist."""
    broken = []
    for target in LINK.findall(page.read_text()):
        if re.match(r"[a-z]+:", target):  # https:, mailto: ...
            continue
        path, _, anchor = target.partition("#")
        linked = (page.parent / path).resolve() if path else page
        if not linked.exists():
            broken.append(f"{target} (no such file)")
        elif anchor and linked.suffix == ".md" and anchor not in heading_anchors(linked.read_text()):
            broken.append(f"{target} (no such section)")
    return broken


def test_heading_anchors_follow_github() -> None:
    text = (
        "# Speed\n## Side by side with ManiSkill (`benchmarks/vs_maniskill.py`)\n## Speed\n```\n# not a heading\n```\n"
    )
    assert heading_anchors(text) == {"speed", "side-by-side-with-maniskill-benchmarksvs_maniskillpy", "speed-1"}


def test_broken_links_are_found(tmp_path: Path) -> None:
    (tmp_path / "a.md").write_text("# Alpha\nSee [b](b.md#beta), [gone](c.md) and [no](b.md#gamma).\n")
    (tmp_path / "b.md").write_text("## Beta\n")
    assert broken_links(tmp_path / "a.md") == ["c.md (no such file)", "b.md#gamma (no such section)"]


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_relative_links_resolve(page: Path) -> None:
    assert broken_links(page) == []
