"""Can a robot's URDF be used: its links (XML), and whether DART loads it, remembered between processes.

The checker asks DART to load every robot's URDF (E504 when it cannot), but
importing DART and loading the arm takes a third of a second, more than the
rest of `vkgc check`. A URDF DART has loaded is therefore remembered in the
cache folder (`vkgl.resources.cache_folder`), keyed by everything the load
depends on: the URDF's bytes and where it is (relative mesh paths are
resolved from there), the bytes of every mesh file it names, and the DART
library itself (its file's path, size and time). The next check of the same
URDF asks the cache, not DART, and gives the same verdict. Only successes are
kept: a URDF DART rejects is loaded again, so that DART prints its reasons each
time. A URDF that names files by URI (`package://`), which DART resolves by
its own search, is never cached.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
import xml.etree.ElementTree as ET
from functools import lru_cache
from pathlib import Path

from vkgl.atomic import write_text
from vkgl.errors import InputError
from vkgl.lang.syntax.sources import not_a_regular_file
from vkgl.resources import cache_folder

_CACHE_VERSION = "vkg-urdf-dart/1"  # part of the key: a new meaning of the key forgets the old entries


@lru_cache(maxsize=16)
def urdf_links(path: str) -> tuple[frozenset[str], str | None]:
    """The link names of a URDF and, if it cannot be used, why (XML first, then DART)."""
    problem = not_a_regular_file(path)
    if problem:
        return frozenset(), problem
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        return frozenset(), f"not valid XML ({exc})"
    if root.tag != "robot":
        return frozenset(), f"the root element is <{root.tag}>, not <robot>"
    links = frozenset(link.get("name", "") for link in root.iter("link"))
    if not links:
        return links, "it declares no <link>"
    return links, dart_problem(path, root)


def dart_problem(path: str, root: ET.Element) -> str | None:
    """Why DART cannot load the URDF at `path` (whose XML is `root`), or None when it can."""
    key = _key(path, root)
    if key is not None and _known_good(key):
        return None
    problem = _load_in_dart(path)
    if problem is None and key is not None:
        _remember(key)
    return problem


def _load_in_dart(path: str) -> str | None:
    import dartpy as dart

    skeleton = dart.utils.DartLoader().parseSkeleton(str(Path(path).resolve()))
    return None if skeleton is not None else "DART cannot load it (see its messages above)"


def _key(path: str, root: ET.Element) -> str | None:
    """The hash of everything DART's verdict on the URDF depends on, or None if that cannot be known here."""
    dart = _dart_identity()
    if dart is None:
        return None
    urdf = Path(path).resolve()
    digest = hashlib.sha256()
    for part in (_CACHE_VERSION, dart, str(urdf)):
        digest.update(part.encode("utf-8") + b"\0")
    try:
        digest.update(urdf.read_bytes())
        for name in sorted({e.get("filename", "") for e in root.iter() if e.get("filename") is not None}):
            referenced = _local_file(urdf.parent, name)
            if referenced is None:
                return None
            digest.update(b"\0" + name.encode("utf-8") + b"\0")
            digest.update(referenced.read_bytes() if referenced.is_file() else b"<missing>")
    except OSError:
        return None
    return digest.hexdigest()


def _local_file(folder: Path, name: str) -> Path | None:
    """The file a URDF's `filename` names, or None for a URI DART resolves by its own search."""
    if name.startswith("file://"):
        name = name[len("file://") :]
    elif "://" in name:
        return None
    return folder / name


def _dart_identity() -> str | None:
    """Which DART would load the URDF (found without importing it): its file, size and time."""
    spec = importlib.util.find_spec("dartpy")
    if spec is None or spec.origin is None:
        return None
    try:
        stat = os.stat(spec.origin)
    except OSError:
        return None
    return f"{spec.origin}:{stat.st_size}:{stat.st_mtime_ns}"


def _entry(key: str) -> Path | None:
    folder = cache_folder()
    return None if folder is None else folder / f"urdf-{key[:32]}.dart-ok"


def _known_good(key: str) -> bool:
    entry = _entry(key)
    try:
        return entry is not None and entry.read_text(encoding="utf-8").strip() == key
    except (OSError, UnicodeDecodeError):
        return False


def _remember(key: str) -> None:
    """Keep `key` as loaded by DART (a cache file, written by the one atomic writer; a failure is only a slower
    next check)."""
    entry = _entry(key)
    if entry is None:
        return
    with contextlib.suppress(OSError, InputError):
        entry.parent.mkdir(parents=True, exist_ok=True)
        write_text(entry, key + "\n")
