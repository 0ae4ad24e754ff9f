"""Diagnostic codes of modules and files (E5xx) and the warnings (W6xx), re-exported by `codes`."""

from __future__ import annotations

from vkgl.lang.diagnostics.registry import register as _code

# modules and files (resolve.py, checks.py)
MISSING_MODULE = _code(
    "E501",
    "missing module",
    (
        "A `use` names a module that does not exist. For `use a.b.c` the message lists every directory "
        "searched, in order (the importing file's directory, each `VKG_PATH` entry, the installed stdlib's "
        "parent; for `use stdlib.x` only the installed stdlib, one stdlib per compilation); a note suggests "
        'the closest module name. For `use "path.vkg"` the path is relative to the importing file, not the '
        "working directory."
    ),
)
IMPORT_CYCLE = _code(
    "E502",
    "import cycle",
    (
        "Modules import each other in a circle. The message prints the cycle; the error is reported at the "
        "`use` that closes it. Remove one of the `use` lines (move the shared declarations to a third module "
        "that both use)."
    ),
)
MESH_UNREADABLE = _code(
    "E503",
    "mesh file missing or unreadable",
    (
        "A mesh file is missing, or trimesh cannot read triangles from it (the message says what trimesh "
        "said), or its triangles bound no volume (fewer than 4 vertices, or all on one plane: a flat mesh "
        "cannot be a solid body that stands on a table or is pushed), or it is larger than the limit for a "
        "mesh (the message gives it). Mesh paths are relative to the module's file."
    ),
)
URDF_UNREADABLE = _code(
    "E504",
    "URDF file missing or unreadable",
    (
        "A robot's URDF file is missing, is not XML with a `<robot>` root and `<link>`s, or DART cannot load "
        "it. URDF paths are relative to the module's file."
    ),
)
SOURCE_UNREADABLE = _code(
    "E505",
    "source file missing or unreadable",
    (
        "A source file (given on the command line or by `use`) cannot be read: missing, a directory, not "
        "readable, or not UTF-8 text. Name `.vkg` files (`vkgc check examples/tasks/*.vkg`); save sources as "
        "UTF-8."
    ),
)
NOT_REGULAR_FILE = _code(
    "E506",
    "not a regular file",
    (
        "A source file (given on the command line or by `use`) is a directory, a named pipe (FIFO), a device, a"
        " socket or a symbolic-link loop. VKG reads regular files only, and looks before it opens (a FIFO would"
        " wait forever, `/dev/zero` never ends). Name the `.vkg` file itself."
    ),
)
SOURCE_TOO_LARGE = _code(
    "E507",
    "source file too large",
    (
        "A source file is larger than 10 MiB (`vkgl.lang.syntax.sources.MAX_SOURCE_BYTES`); no hand-written or "
        "generated module comes near it. Split it into modules joined by `use`."
    ),
)
NOT_UTF8 = _code(
    "E508",
    "source file not UTF-8",
    (
        "A source file holds bytes that are not UTF-8 text. The message gives the first bad byte and its line "
        "and column (counted in characters); the file's text is not shown. Save the file as UTF-8."
    ),
)
USE_NOT_VKG = _code(
    "E509",
    "a source that is not a .vkg file",
    (
        '`use "PATH"` names a file whose name does not end in `.vkg` (`use "/etc/passwd"`), or a source (named '
        "by `use` or on the command line) is a symbolic link, or lies in a linked folder, and the file it "
        "finally names does not end in `.vkg` (`pw.vkg` linking to `/etc/passwd`). Only `.vkg` files are read "
        "as sources: the file is not read, and its text is never shown. A file named on the command line that "
        "is not a link is read whatever its name (you chose it). Name the `.vkg` file itself."
    ),
)

TOO_MANY_TOKENS = _code(
    "E510",
    "a source file with too many tokens",
    (
        "A source file holds at most 200,000 tokens (names, numbers, units and marks such as `(` or `,`; "
        "comments do not count): compiling costs memory per token, and a file past the limit (a few megabytes "
        "of declarations) would take gigabytes and minutes. The error is at the first token past the limit. "
        "A 10,000-body scene is about 140,000 tokens. Split the file into modules joined by `use`."
    ),
)
MESH_TOO_LARGE = _code(
    "E511",
    "a mesh file too large",
    (
        "A mesh has at most 500,000 triangles and its file at most 128 MiB: the checks, the simulator and the "
        "planner each hold it in memory (a mesh of 1.3 million triangles took 2.2 GB and 22 s to check). A "
        "binary STL is refused from its header, before it is read. Simplify the mesh (e.g. decimate it: a "
        "collision shape rarely needs more than a few thousand triangles)."
    ),
)

# warnings (checks.py)
NOTHING_CAN_MOVE = _code(
    "W601",
    "a goal body that no imported affordance can move",
    (
        "A warning (exit 0): a task's goal body has no affordance in the compilation, so no plan can move it."
        " `use` its affordance module (`use stdlib.affordances.block`) or learn one with `vkgc learn`; for a"
        " body the stdlib has no affordances for, the note gives the `use` of the module `vkgc learn` already"
        " wrote for the body's file (where it writes without `-o`), else the `vkgc learn` command for that file."
    ),
)
TOOL_WITHOUT_CORRESPONDENCE = _code(
    "W602",
    "a tool frame with no correspondence in a task's scene",
    (
        "A warning (exit 0): a task's scene holds a tool (a body explored while grasped) but no "
        "correspondence names any of its frames, so the planner can never use it. `use stdlib.tools`, or "
        "declare `correspondences { Tool.tip ~ fingertip }`."
    ),
)
SHADOWED_STDLIB = _code(
    "W603",
    "a local stdlib module that differs from the installed one, which is used",
    (
        "A warning (exit 0): a compilation uses one stdlib, the installed one, so `use stdlib.X` reads the "
        "installed `stdlib/X.vkg`, never a `stdlib/X.vkg` beside the importing file or in a `VKG_PATH` entry. "
        "When such a local file exists and differs from the installed one, the message names both: give your "
        "module a name outside `stdlib` (`use mylib.tools`), or install your changed stdlib "
        "(`pip install -e .` in your checkout). An identical copy (a source checkout's `stdlib/` after "
        "`pip install .`) is not reported."
    ),
)
JOINT_GOAL_PAST_LIMIT = _code(
    "W604",
    "a joint goal past its joint's limits",
    (
        "A warning (exit 0): `goal B open Q` asks for a joint coordinate outside the limits of B's joint, by "
        'more than the goal\'s tolerance, so no plan can reach it (`vkgc solve` answers "no plan", exit 2, '
        "with the same numbers). The message gives the goal and the limit it passes, in the goal's unit. Open "
        "it within the joint's `limits`, or widen them if the real joint goes further."
    ),
)
