"""Which documents the language server knows, and by what name: the open buffers only, keyed as pygls keys them.

pygls files an open document under its URI percent-decoded (`unquote`), so
`file:///tmp/my%20tasks/t.vkg` and `file:///tmp/my tasks/t.vkg` are one
document; the server keys its own state the same way (`document_key`).

The compiler knows a document by a path (`document_path`): the file a `file:`
URI names, resolved; for a URI that names no file of this machine (`untitled:`
buffers, other schemes, a Windows drive letter on Linux) a name under a
`.vkgc-untitled` folder of the workspace that no file has. The buffer is
compiled from memory under that name (its `use` lines start from the
workspace), and nothing is ever read from disk for it.
"""

from __future__ import annotations

import hashlib
import os
import re
from pathlib import Path
from urllib.parse import unquote

from pygls.uris import to_fs_path

UNTITLED_FOLDER = ".vkgc-untitled"


def document_key(uri: str) -> str:
    """The key of the document `uri` in pygls's workspace (and in the server's own tables)."""
    return unquote(uri)


def document_path(uri: str, home: Path) -> Path:
    """The resolved path the compiler knows the document `uri` by (see the module's docstring)."""
    path = to_fs_path(uri)
    if path is not None and os.path.isabs(path):
        return Path(path).resolve()
    digest = hashlib.sha256(document_key(uri).encode("utf-8", "surrogatepass")).hexdigest()[:12]
    stem = re.sub(r"[^\w.-]+", "_", Path(unquote(uri).replace("\\", "/")).stem or "untitled")[:40]
    return (home / UNTITLED_FOLDER / f"{stem}-{digest}.vkg").resolve()
