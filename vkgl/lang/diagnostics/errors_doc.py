"""docs/errors.md, generated: every code of the registry (vkgl/lang/diagnostics/codes.py) with its golden example.

    python -m vkgl.lang.diagnostics.errors_doc > docs/errors.md      # from the repository root

Each code's section shows its explanation, the input of each golden case
(tests/lang/golden/<CODE>_*.vkg), the helper modules it uses and the exact
`vkgc check` output (<same>.expected). tests/lang/diagnostics/test_golden.py checks that
docs/errors.md is exactly this text.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from vkgl.lang.diagnostics.codes import CODES

# Modules of tests/lang/golden/lib/ that a case uses, shown under it (by the case's file name).
HELPERS = {
    "E201_wrong_dimension": ["lib/scene.vkg"],
    "E201_angle_as_position_tolerance": ["lib/scene.vkg"],
    "E201_joint_goal_of_the_wrong_kind": ["lib/kitchen.vkg"],
    "E202_joint_goal_without_a_unit": ["lib/kitchen.vkg"],
    "E306_goal_not_in_scene": ["lib/scene.vkg"],
    "E410_task_without_goal": ["lib/scene.vkg"],
    "E423_goal_off_table": ["lib/scene.vkg"],
    "E424_goal_in_robot_base": ["lib/scene.vkg"],
    "E441_no_joint_to_open": ["lib/kitchen.vkg"],
    "W601_nothing_can_move": ["lib/scene.vkg"],
    "W601_own_body_learned": ["lib/bodies/bracket.vkg", "lib/affordances/bracket.vkg"],
    "W604_joint_goal_past_the_limit": ["lib/kitchen.vkg"],
    "E502_import_cycle": ["lib/cycle_back.vkg"],
    "W603_local_stdlib_shadows": ["stdlib/tools.vkg"],
}
# What a case that is itself a symbolic link points to (its target is never shown).
LINK_NOTES = {
    "E509_command_line_link": "a stand-in for `/etc/passwd` (a line of a password file), named on the command line.",
}
# What a case's helper file is, when it cannot be shown as text.
FILE_NOTES = {
    "E505": "where `golden/lib/dangling.vkg` is a symbolic link to `no_such_target.vkg`, which does not exist.",
    "E506": "where `golden/lib/loop.vkg` is a symbolic link to itself.",
    "E507": "where `golden/lib/too_large.vkg` is an 11 MiB file (the golden test makes it).",
    "E510": "where `golden/lib/many_tokens.vkg` is a comment line and 20,001 lines `x = (1, 2, 3) m` (the golden "
    "test makes it).",
    "E511": "where `golden/lib/huge_mesh.stl` is a binary STL whose header says 600,000 triangles (the golden test "
    "makes it).",
    "E508": "where `golden/lib/latin1.vkg` is saved in Latin-1 (the byte `\\xe9` for `é`).",
}

# What a single case's helper file is, when it is not a module.
CASE_NOTES = {
    "E503_mesh_unreadable": "where `golden/lib/not_a_mesh.stl` holds the text `this is not a mesh`.",
    "E503_flat_mesh": "where `golden/lib/one_triangle.stl` is an ASCII STL of one triangle (3 vertices on one plane).",
}


def errors_doc(repo: Path = Path(".")) -> str:
    """The text of docs/errors.md for the checkout at `repo` (its golden cases are read from there)."""
    golden = repo / "tests" / "lang" / "golden"
    out = [
        "# Diagnostics: every code",
        "",
        "`vkgc check` (and every command that compiles a `.vkg` file) reports problems as",
        "",
        "```",
        "path:line:col: error[CODE]: message",
        "    the source line",
        "    ^^^^^ (under the span)",
        "    note: a hint, when there is one",
        "```",
        "",
        "It reports every error it can find, sorted by file and position, then a summary",
        "line; it exits 1 if there is any error and 0 otherwise (warnings, `W...`, do not",
        "fail a run). After a syntax error (E1xx) the parser skips to the next declaration",
        "that starts a line (`body`, `scene`, ... in column 1), so each broken declaration",
        "gives one error; the other checks of that file run once its syntax errors are fixed.",
        "Codes are stable. `vkgl/lang/diagnostics/codes.py` holds the list; each code below has the",
        "example input of its golden test (`tests/lang/golden/`) and the exact output of",
        "`vkgc check` on it, run from the repository root. This page is generated from",
        "both: `python -m vkgl.lang.diagnostics.errors_doc > docs/errors.md` (a test checks it is current).",
        "",
        "| code | meaning |",
        "|---|---|",
    ]
    for code, entry in CODES.items():
        out.append(f"| [{code}](#{code.lower()}) | {entry.meaning} |")
    out.append("")
    for code, entry in CODES.items():
        meaning = entry.meaning
        cases = sorted(golden.glob(f"{code}_*.vkg"))
        out += [f"## {code}", "", f"**{meaning[0].upper() + meaning[1:]}.** " + entry.explanation, ""]
        for case in cases:
            src = "" if case.is_symlink() else case.read_text(encoding="utf-8")
            if code == "E104":
                lines = src.rstrip("\n").split("\n")
                src = (
                    "\n".join(
                        lines[:6]
                        + [
                            "            ...        # 33 unions deep in all",
                            "            box (1, 1, 1) cm at (0, 0, 0) cm",
                            "            ...",
                        ]
                        + lines[-3:]
                    )
                    + "\n"
                )
            shown = case.relative_to(golden.parent).as_posix()
            if case.is_symlink():  # the case is a link to a file that is not a module: never quoted, here neither
                out += [f"`{shown}` is a symbolic link to `{os.readlink(case)}`, {LINK_NOTES[case.stem]}", ""]
            else:
                out += [f"`{shown}`:", "", "```", src.rstrip("\n"), "```", ""]
            for helper in HELPERS.get(case.stem, []):
                text = (golden / helper).read_text(encoding="utf-8")
                out += [f"with `golden/{helper}`:", "", "```", text.rstrip("\n"), "```", ""]
            if code in FILE_NOTES:
                out += [FILE_NOTES[code], ""]
            if case.stem in CASE_NOTES:
                out += [CASE_NOTES[case.stem], ""]
            out += [
                "`vkgc check` prints:",
                "",
                "```",
                case.with_suffix(".expected").read_text(encoding="utf-8").rstrip("\n"),
                "```",
                "",
            ]
    return "\n".join(out)


def main() -> None:
    """Print docs/errors.md for the checkout in the working directory."""
    sys.stdout.write(errors_doc(Path(".")))


if __name__ == "__main__":
    main()
