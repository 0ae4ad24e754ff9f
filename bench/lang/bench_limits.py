"""Memory and time of `vkgc check` on inputs at and past the front end's size limits (issue 25, item 12).

Run on demand: `PYTHONPATH=$PWD python bench/lang/bench_limits.py`. Each case is
checked in a fresh process (`vkgc check`); the table gives its exit code, wall
time and peak resident memory (GNU time's, start-up included: about 0.1 GB
for the imports alone). The inputs past a limit are refused with one
diagnostic before they are parsed or loaded, so their cost is that of reading
and counting.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
# Peak memory from GNU time: a child's own ru_maxrss would include the parent's memory at the fork.
TIME = shutil.which("time") or "/usr/bin/time"


def measure(path: Path) -> tuple[int, float, float, str]:
    """Exit code, seconds, peak RSS in GB and the first line of output of `vkgc check path` in a fresh process."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    start = time.perf_counter()
    command = [TIME, "-f", "MAXRSS %M", sys.executable, "-m", "vkgl.cli", "check", path.name]
    done = subprocess.run(command, capture_output=True, text=True, env=env, cwd=path.parent)
    seconds = time.perf_counter() - start
    rss = next((int(line.split()[1]) for line in done.stderr.splitlines() if line.startswith("MAXRSS")), 0)
    first = (done.stdout.splitlines() or [""])[0]
    return done.returncode, seconds, rss / 1e6, first


def bodies_file(count: int, one_line: bool = False) -> str:
    """`count` small bodies (about 49 bytes each), one per line or all on one line."""
    rows = [f"body B{i} {{ shape box (1, 1, 1) cm mass 1 kg }}" for i in range(count)]
    return (" " if one_line else "\n").join(rows) + "\n"


def scene_file(bodies: int) -> str:
    """A scene of `bodies` blocks 0.8 m apart on a 100 m table (about 16 tokens a line)."""
    rows = ["use stdlib.robots.panda", "use stdlib.bodies.block", "", "scene crowded {"]
    rows += ["    table size (100, 100) m at (0, 0, 0) m", "    robot arm : Panda at (-49.5, -49.5, 0) m"]
    for i in range(bodies):
        x, y = i % 120 * 0.8 - 47, i // 120 * 0.8 - 47
        rows.append(f"    b{i} : Block on table at ({x:.2f}, {y:.2f}) m yaw {i % 360}deg")
    return "\n".join([*rows, "}"]) + "\n"


def mesh_case(folder: Path, subdivisions: int) -> Path:
    """A body whose mesh is an icosphere of 20 * 4**subdivisions faces (binary STL)."""
    import trimesh

    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.05)
    stl = folder / f"sphere{subdivisions}.stl"
    mesh.export(stl)
    source = folder / f"sphere{subdivisions}.vkg"
    source.write_text(f'body Ball {{\n    shape mesh "{stl.name}"\n    mass 0.2 kg\n}}\n', encoding="utf-8")
    return source


def main() -> None:
    from vkgl.lang.ir.mesh_limits import MAX_MESH_FACES
    from vkgl.lang.syntax.parser import MAX_TOKENS

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cases: list[tuple[str, Callable[[], Path]]] = []

        def text_case(name: str, text: str) -> Callable[[], Path]:
            def make() -> Path:
                path = folder / name
                path.write_text(text, encoding="utf-8")
                return path

            return make

        cases += [
            ("an empty file (start-up alone)", text_case("empty.vkg", "")),
            ("scene of 10,000 blocks (about 140 K tokens: within)", text_case("scene10k.vkg", scene_file(10_000))),
            ("scene of 12,000 blocks (about 190 K tokens: within)", text_case("scene12k.vkg", scene_file(12_000))),
            ("100,000 bodies in 4.9 MB (refused)", text_case("bodies100k.vkg", bodies_file(100_000))),
            ("9 MB on one line (refused)", text_case("oneline.vkg", bodies_file(180_000, one_line=True))),
            ("mesh of 327,680 faces (within)", lambda: mesh_case(folder, 7)),
            ("mesh of 1,310,720 faces (refused)", lambda: mesh_case(folder, 8)),
        ]
        print(f"limits: {MAX_TOKENS:,} tokens per source file, {MAX_MESH_FACES:,} faces per mesh")
        print()
        print("| input | size | exit | time | peak memory | first line |")
        print("|---|---|---|---|---|---|")
        for name, make in cases:
            path = make()
            size = sum(p.stat().st_size for p in folder.glob(path.stem + ".*"))
            status, seconds, rss, first = measure(path)
            print(f"| {name} | {size / 1e6:.1f} MB | {status} | {seconds:.1f} s | {rss:.2f} GB | {first[:90]} |")


if __name__ == "__main__":
    main()
