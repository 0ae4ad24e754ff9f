"""Benchmark: the front end's speed (parse, check) against the targets of issue 2.

    python bench/lang/bench_frontend.py [--repeat N]

Prints one Markdown table: parse and check time of every file of examples/ and
stdlib/, then the issue's targets:

- parsing + checking all of examples/ and stdlib/ in under 0.3 s after start-up
  (in-process, grammar built and DART loaded once, no parse cache);
- a generated 10,000-line scene file checks in under 2 s;
- `vkgc --help` starts in under 0.3 s;

and, for scale, a generated module of 1,000 declarations (bodies, scenes,
tasks) and `vkgc check` of everything in a fresh process. Times are the best of
`--repeat` runs (default 3), so that other work on the machine counts less.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def best_of(repeat: int, fn: Callable[[], object], before: Callable[[], None] = lambda: None) -> float:
    """The fastest of `repeat` runs of `fn`, in seconds (`before` runs untimed before each)."""
    times = []
    for _ in range(repeat):
        before()
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def clear_parse_cache() -> None:
    from vkgl.lang import module_cache
    from vkgl.lang.syntax import parser

    parser.parse_cache().clear()
    module_cache.forget_read_back()


def vkg_files() -> list[Path]:
    return sorted([*(REPO / "examples").rglob("*.vkg"), *(REPO / "stdlib").rglob("*.vkg")])


def scene_file(lines: int) -> str:
    """A scene of about `lines` lines: a table, a robot and one block per line."""
    rows = [
        "use stdlib.robots.panda",
        "use stdlib.bodies.block",
        "",
        "scene crowded {",
        "    table size (100, 100) m at (0, 0, 0) m",
        "    robot arm : Panda at (-1, -1, 0) m",  # clear of the blocks (E420)
    ]
    for i in range(lines - len(rows) - 1):
        rows.append(f"    b{i} : Block on table at ({i % 100 * 0.5:.2f}, {i // 100 * 0.5:.2f}) m yaw {i % 360}deg")
    rows.append("}")
    return "\n".join(rows) + "\n"


def thousand_declarations() -> str:
    """A module of 1,000 declarations: 500 bodies, 250 scenes that place them, 250 tasks on those scenes."""
    rows = ["use stdlib.robots.panda", ""]
    for i in range(500):
        rows += [
            f"body B{i} {{",
            f"    shape box ({10 + i % 7}, 20, 5) cm",
            "    mass 0.5 kg",
            "    friction 0.4",
            f"    frame tip = ({i % 9}, 0, 0) cm yaw 90deg",
            "}",
        ]
    for i in range(250):
        rows += [
            f"scene s{i} {{",
            "    table size (1.6, 1.2) m at (0.5, 0, 0) m",
            "    robot arm : Panda at (0, 0, 0) m",
            f"    a : B{2 * i} on table at (0.45, 0.1) m yaw 0deg",
            f"    b : B{2 * i + 1} on table at (0.45, -0.2) m",
            "}",
        ]
    for i in range(250):
        rows += [
            f"task t{i} {{",
            f"    scene s{i}",
            "    goal a at (0.6, 0.0) m yaw 0deg within 1 cm, 3 deg",
            "    search { max_depth 4  timeout 10 s }",
            "}",
        ]
    return "\n".join(rows) + "\n"


def row(what: str, seconds: float, target: float | None = None, note: str = "") -> str:
    verdict = "" if target is None else ("ok" if seconds < target else "SLOW")
    shown_target = "" if target is None else f"< {target * 1000:.0f} ms"
    return f"| {what} | {seconds * 1000:.1f} ms | {shown_target} | {verdict} | {note} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    repeat = max(1, args.repeat)

    start = time.perf_counter()
    from vkgl.lang.compiler import check_files
    from vkgl.lang.syntax.parser import _parse_uncached

    # Start-up: imports, the grammar's LALR tables, DART (the stdlib URDF is checked once).
    check_files([str(REPO / "stdlib" / "tools.vkg")])
    startup = time.perf_counter() - start
    kept = os.environ.get("VKGL_CACHE_DIR")
    os.environ["VKGL_CACHE_DIR"] = "off"  # in this process every check parses: no parse read back from the cache folder

    files = vkg_files()
    print("| file | lines | parse | check (with imports) |")
    print("|---|---|---|---|")
    for path in files:
        text = path.read_text(encoding="utf-8")
        shown = str(path.relative_to(REPO))
        parse = best_of(repeat, lambda text=text, shown=shown: _parse_uncached(text, shown))
        check = best_of(repeat, lambda path=path: check_files([str(path)]), clear_parse_cache)
        print(f"| {shown} | {len(text.splitlines())} | {parse * 1000:.2f} ms | {check * 1000:.2f} ms |")
    print()

    print("| measurement | time | target | | notes |")
    print("|---|---|---|---|---|")
    print(row("start-up in process (imports, grammar, DART)", startup, note="once per process"))
    names = [str(p) for p in files]
    everything = best_of(repeat, lambda: check_files(names), clear_parse_cache)
    print(row(f"parse + check all of examples/ and stdlib/ ({len(files)} files)", everything, 0.3, "after start-up"))

    with tempfile.TemporaryDirectory() as tmp:
        big_scene = Path(tmp) / "crowded.vkg"
        big_scene.write_text(scene_file(10_000), encoding="utf-8")
        diagnostics, _ = check_files([str(big_scene)])
        assert not [d for d in diagnostics if d.is_error], diagnostics[:3]
        seconds = best_of(repeat, lambda: check_files([str(big_scene)]), clear_parse_cache)
        print(row("check a generated 10,000-line scene file", seconds, 2.0, "10,000 lines, 9,993 bodies"))

        thousand = Path(tmp) / "thousand.vkg"
        thousand.write_text(thousand_declarations(), encoding="utf-8")
        diagnostics, _ = check_files([str(thousand)])
        assert not [d for d in diagnostics if d.is_error], diagnostics[:3]
        text = thousand.read_text(encoding="utf-8")
        parse = best_of(repeat, lambda: _parse_uncached(text, "thousand.vkg"))
        check = best_of(repeat, lambda: check_files([str(thousand)]), clear_parse_cache)
        lines = len(text.splitlines())
        print(row(f"parse a generated 1,000-declaration module ({lines} lines)", parse))
        print(row("parse + check the 1,000-declaration module", check))

    if kept is None:  # fresh processes start as a user's do, with the cache folder
        del os.environ["VKGL_CACHE_DIR"]
    else:
        os.environ["VKGL_CACHE_DIR"] = kept
    vkgc = [sys.executable, "-m", "vkgl.cli"]
    help_time = best_of(repeat, lambda: subprocess.run([*vkgc, "--help"], capture_output=True, check=True))
    print(row("`vkgc --help` (fresh process)", help_time, 0.3))
    fresh = best_of(repeat, lambda: subprocess.run([*vkgc, "check", *names], capture_output=True, check=True, cwd=REPO))
    print(row("`vkgc check` examples/ and stdlib/ (fresh process)", fresh, note="start-up included"))


if __name__ == "__main__":
    main()
