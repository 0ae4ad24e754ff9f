"""The repository stands alone: nothing in it points at documents outside it, and its own links resolve.

The project's design notes live outside the repository; a user has only the repository. So no text file
of it may name those notes or the folder beside the checkout that holds them: every contract is in docs/
(the language in docs/language.md, the file formats in docs/formats.md, the method in docs/method.md).
And every relative link of the Markdown documents must lead to a file of the repository and, when it
names a section, to a heading of that file.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

# Spelled in pieces, so that this file does not name what it looks for.
OUTSIDE = [name + ".md" for name in ("LANGUAGE", "ARCHITECTURE", "PAPER", "EXAMPLES")] + [".." + "/shared"]
SKIPPED_DIRS = {".git", ".venv", "__pycache__", ".mypy_cache", ".ruff_cache", ".pytest_cache", ".hypothesis"}


def repository_files() -> list[Path]:
    """The files git tracks, and the new ones it does not ignore; every file outside caches without git."""
    try:
        listed = subprocess.run(
            ["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
            cwd=REPO,
            capture_output=True,
            check=True,
        ).stdout.decode("utf-8")
    except (OSError, subprocess.CalledProcessError):  # not a git checkout (an unpacked archive)
        return [p for p in REPO.rglob("*") if p.is_file() and not SKIPPED_DIRS & set(p.relative_to(REPO).parts)]
    return [REPO / name for name in listed.split("\0") if name and (REPO / name).is_file()]


def text_of(path: Path) -> str | None:
    """The file's text, or None for a binary file (not UTF-8, or with NUL bytes)."""
    data = path.read_bytes()
    if b"\0" in data:
        return None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return None


def test_no_file_names_a_document_outside_the_repository() -> None:
    found = []
    files = repository_files()
    assert len(files) > 100, "the repository's files were not found"
    for path in files:
        text = text_of(path)
        if text is None:
            continue
        for number, line in enumerate(text.splitlines(), start=1):
            found += [f"{path.relative_to(REPO)}:{number}: {name}" for name in OUTSIDE if name in line]
    assert found == [], "link to the repository's own documents instead:\n" + "\n".join(found)


def test_the_check_would_see_a_reference(tmp_path: Path) -> None:
    """The search is not vacuous: a line naming a design note is found in a text file, and binaries are skipped."""
    note = tmp_path / "note.md"
    note.write_text(f"see {OUTSIDE[0]} section 3\n", encoding="utf-8")
    assert any(name in (text_of(note) or "") for name in OUTSIDE)
    (tmp_path / "blob.bin").write_bytes(b"\x89PNG\0" + OUTSIDE[1].encode())
    assert text_of(tmp_path / "blob.bin") is None


def markdown_files() -> list[Path]:
    """README.md and the documents of docs/."""
    return [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]


def heading_anchors(path: Path) -> set[str]:
    """The anchors GitHub gives the headings of a Markdown file (lower case, punctuation dropped, - for spaces)."""
    text = re.sub(r"^```.*?^```", "", path.read_text(encoding="utf-8"), flags=re.S | re.M)  # no code blocks
    anchors = set()
    for heading in re.findall(r"^#{1,6} +(.+?) *#*$", text, flags=re.M):
        anchors.add(re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-"))
    return anchors


LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


@pytest.mark.parametrize("page", markdown_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_relative_links_lead_to_a_file_and_a_heading(page: Path) -> None:
    text = re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.S | re.M)
    broken = []
    for target in LINK.findall(text):
        if re.match(r"[a-z]+:", target):  # https:, mailto:
            continue
        file_part, _, anchor = target.partition("#")
        linked = (page.parent / file_part).resolve() if file_part else page
        if not linked.exists() or REPO not in linked.parents:
            broken.append(f"{target}: no such file in the repository")
        elif anchor and linked.suffix == ".md" and anchor not in heading_anchors(linked):
            broken.append(f"{target}: {linked.name} has no heading with that anchor")
    assert broken == [], f"{page.relative_to(REPO)}:\n" + "\n".join(broken)
