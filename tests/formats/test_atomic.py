"""The one writer of outputs (vkgl.atomic): whole or not at all, never renamed over what is not a file."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest
from rename_guard import no_rename_outside_the_temporary_folder  # noqa: F401 (an autouse fixture)

from vkgl import atomic
from vkgl.atomic import Way
from vkgl.errors import InputError


def _no_rename(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("renamed over a file that is not a regular file")

    monkeypatch.setattr(atomic.os, "replace", refuse)
    monkeypatch.setattr(atomic.os, "rename", refuse)


def test_a_new_file_and_a_regular_file_are_replaced(tmp_path: Path) -> None:
    path = tmp_path / "out.json"
    assert atomic.decide(path) == (Way.REPLACE, path)
    atomic.write_text(path, "one")
    os.chmod(path, 0o640)
    atomic.write_text(path, "two")
    assert path.read_text() == "two"
    assert stat.S_IMODE(path.stat().st_mode) == 0o640  # the old file's permissions are kept
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]


def test_a_character_device_is_written_in_place_never_renamed_over(monkeypatch: pytest.MonkeyPatch) -> None:
    """`--json /dev/null` as root replaced the system's /dev/null with a regular file."""
    assert atomic.decide("/dev/null") == (Way.IN_PLACE, Path("/dev/null"))
    _no_rename(monkeypatch)
    atomic.write_bytes("/dev/null", b"{}\n")  # opened for writing, as `> /dev/null` does
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_a_fifo_is_fed_not_replaced(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    fifo = tmp_path / "plan.fifo"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        _no_rename(monkeypatch)
        atomic.write_text(fifo, '{"format": "vkg-plan/8"}\n')
        assert os.read(reader, 1 << 16) == b'{"format": "vkg-plan/8"}\n'
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_a_fifo_nobody_reads_is_refused_at_once(tmp_path: Path) -> None:
    fifo = tmp_path / "plan.fifo"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"named pipe \(FIFO\) that no process reads"):
        atomic.write_text(fifo, "{}")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_a_link_is_kept_and_its_target_written(tmp_path: Path) -> None:
    target = tmp_path / "real" / "task.vkg"
    target.parent.mkdir()
    target.write_text("old")
    link = tmp_path / "link.vkg"
    os.symlink(target, link)
    assert atomic.decide(link) == (Way.REPLACE, target.resolve())
    atomic.write_text(link, "new")
    assert link.is_symlink() and target.read_text() == "new"
    assert sorted(p.name for p in target.parent.iterdir()) == ["task.vkg"]


def test_a_link_to_a_device_writes_the_device(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    link = tmp_path / "out.json"
    os.symlink("/dev/null", link)
    assert atomic.decide(link)[0] is Way.IN_PLACE
    _no_rename(monkeypatch)
    atomic.write_text(link, "{}")
    assert link.is_symlink()


@pytest.mark.parametrize("name", ["/dev/stdout", "/proc/self/fd/1", "/dev/fd/1"])
def test_stdout_gets_the_bytes_after_what_was_printed(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    print("before")
    assert atomic.decide(name)[0] is Way.STREAM
    atomic.write_text(name, '{"a": 1}\n')
    print("after")
    assert capsys.readouterr().out == 'before\n{"a": 1}\nafter\n'


def test_a_directory_a_loop_and_a_socket_are_refused(tmp_path: Path) -> None:
    import socket

    with pytest.raises(InputError, match="is a directory"):
        atomic.write_text(tmp_path, "x")
    loop = tmp_path / "loop.json"
    os.symlink(loop, loop)
    with pytest.raises(InputError, match="symbolic link loop"):
        atomic.write_text(loop, "x")
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(tmp_path / "s.sock"))
        with pytest.raises(InputError, match="is a socket"):
            atomic.write_text(tmp_path / "s.sock", "x")


def test_the_temporary_file_is_registered_before_it_exists(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C between creating the temporary file and registering it left a 0-byte `.tmp` file behind."""
    seen: list[bool] = []
    real_open = os.open

    def watching_open(path: object, flags: int, *args: object) -> int:
        if flags & os.O_EXCL:
            seen.append(str(path) in atomic._IN_FLIGHT and not os.path.exists(str(path)))
        return real_open(path, flags, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(atomic.os, "open", watching_open)
    atomic.write_text(tmp_path / "out.vkg", "x")
    assert seen == [True]


def test_an_interrupt_mid_write_leaves_the_old_file_and_no_temporary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "out.vkg"
    path.write_text("old")

    def interrupted(fd: int) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(atomic.os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        atomic.write_text(path, "new")
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.vkg"]
    assert not atomic._IN_FLIGHT


def test_writing_gives_a_file_name_to_writers_that_need_one(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "run.mp4"
    with atomic.writing(path) as temporary:
        assert temporary.parent == tmp_path and temporary.suffix == ".mp4" and temporary != path
        temporary.write_bytes(b"frames")
    assert path.read_bytes() == b"frames"
    assert [p.name for p in tmp_path.iterdir()] == ["run.mp4"]
    with pytest.raises(RuntimeError), atomic.writing(path) as temporary:
        temporary.write_bytes(b"half")
        raise RuntimeError("ffmpeg failed")
    assert path.read_bytes() == b"frames" and [p.name for p in tmp_path.iterdir()] == ["run.mp4"]
    with atomic.writing("/dev/stdout") as temporary:
        temporary.write_bytes(b"to the stream\n")
    assert capsys.readouterr().out == "to the stream\n"


def test_every_output_of_vkgl_goes_through_the_one_writer() -> None:
    """Issue 22: two atomic writers (`api._write_text` had no fsync and was unknown to the Ctrl-C handler)."""
    import ast

    package = Path(atomic.__file__).resolve().parent
    writes = {"replace", "rename", "write_text", "write_bytes", "savefig", "save", "mkstemp", "NamedTemporaryFile"}
    found = []
    for module in sorted(package.rglob("*.py")):
        if module == Path(atomic.__file__).resolve():
            continue
        for node in ast.walk(ast.parse(module.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            method = isinstance(node.func, ast.Attribute)  # `path.write_text(...)`, not atomic's own `write_text(...)`
            name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            into_memory = bool(node.args) and isinstance(node.args[0], ast.Name) and node.args[0].id == "buffer"
            receiver = ast.unparse(node.func.value) if isinstance(node.func, ast.Attribute) else ""
            string_method = name in ("replace", "rename") and receiver not in ("os", "shutil")  # str.replace
            if method and name in writes and not (into_memory or string_method or _is_formats_call(node)):
                found.append(f"{module.relative_to(package)}:{node.lineno} {name}")
            modes = [*node.args[1:2], *(k.value for k in node.keywords if k.arg == "mode")]
            if name == "open" and any(_writes_mode(arg) for arg in modes):
                found.append(f"{module.relative_to(package)}:{node.lineno} open for writing")
    assert found == []


def _is_formats_call(node: object) -> bool:
    """`trials.save(path)`: a format's own writer, which writes through `vkgl.atomic`."""
    import ast

    assert isinstance(node, ast.Call)
    return (
        isinstance(node.func, ast.Attribute) and node.func.attr == "save" and ast.unparse(node.func.value) == "trials"
    )


def _writes_mode(arg: object) -> bool:
    import ast

    return isinstance(arg, ast.Constant) and isinstance(arg.value, str) and any(c in arg.value for c in "wax+")
