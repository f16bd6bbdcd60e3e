"""Review of the output formats: what a demanding user runs into. Each test is the
regression test of one fix: numbers the core cannot take, a stdout that is closed, a `dot`
program (``FOON_DOT``) that exits 0 without a picture, the size message of a tree picture,
characters FOON text holds that JSON and XML writers must handle, GraphML's error for text
XML cannot hold, and ``-o`` onto a device or a pipe."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import foon
import pytest
from conftest import need_program
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_json import validate

EXAMPLE = foon.example().paths
GOAL = json.dumps(
    {
        "label": "ice",
        "states": ["crushed", "frozen"],
        "ingredients": [],
        "container": "drinking glass",
    }
)


def cli(
    *argv: str, env: dict[str, str] | None = None, close_stdout: bool = False
) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run(
        [sys.executable, "-m", "foon", *argv],
        capture_output=not close_stdout,
        stderr=subprocess.PIPE if close_stdout else None,
        check=False,
        env={**os.environ, **(env or {})},
        timeout=300,
        # `foon ... >&-`: the command starts with file descriptor 1 closed.
        preexec_fn=(lambda: os.close(1)) if close_stdout else None,
    )


def one_error_line(p: subprocess.CompletedProcess[bytes]) -> str:
    err = p.stderr.decode()
    assert "Traceback" not in err, err
    lines = [ln for ln in err.splitlines() if ln.startswith("foon: error:")]
    assert len(lines) == 1, err
    return lines[0]


# --- numbers larger than the core takes ----------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "option", "limit"),
    [
        (["plan", "--format", "pddl"], "--cost-scale", 2**32 - 1),
        (["plan", "--format", "svg"], "--max-nodes", 2**64 - 1),
        (["draw", str(EXAMPLE["foon"]), "--goal", GOAL, "--format", "dot"], "--depth", 2**32 - 1),
        (
            [
                "export",
                str(EXAMPLE["foon"]),
                "--format",
                "pddl",
                "--goal",
                GOAL,
                "--kitchen",
                str(EXAMPLE["kitchen"]),
            ],
            "--depth",
            2**32 - 1,
        ),
    ],
)
def test_a_number_too_large_is_a_usage_error_not_a_traceback(
    argv: list[str], option: str, limit: int
) -> None:
    for n in (limit + 1, 10**30):
        p = cli(*argv, option, str(n))
        assert p.returncode == 2, p.stderr.decode()
        assert b"Traceback" not in p.stderr
        assert f"argument {option}: too large".encode() in p.stderr
        assert p.stdout == b""
    if option != "--max-nodes":  # the largest value is taken (dot is not needed for these)
        p = cli(*argv, option, str(limit))
        assert p.returncode == 0, p.stderr.decode()
        assert p.stdout


# --- stdout closed -------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["plan", "--format", "steps"],
        ["plan", "--format", "json"],
        ["plan"],
        ["export", str(EXAMPLE["foon"]), "--format", "json"],
        ["draw", str(EXAMPLE["foon"]), "--format", "dot"],
        ["stats", str(EXAMPLE["foon"])],
        ["compare", "--format", "csv"],
    ],
)
def test_a_closed_stdout_is_one_error_line(argv: list[str]) -> None:
    p = cli(*argv, close_stdout=True)
    assert p.returncode == 1
    assert "Bad file descriptor" in one_error_line(p)


def test_with_stdout_closed_files_are_still_written(tmp_path: Path) -> None:
    p = cli("plan", "--format", "dot", "--out", str(tmp_path / "trees"), "-q", close_stdout=True)
    assert p.returncode == 0, p.stderr.decode()
    (tree,) = (tmp_path / "trees").iterdir()
    assert tree.read_text().startswith("digraph")
    out = tmp_path / "foon.json"
    p = cli("export", str(EXAMPLE["foon"]), "--format", "json", "-o", str(out), close_stdout=True)
    assert p.returncode == 0, p.stderr.decode()
    assert foon.load(out).fu_count == foon.load(EXAMPLE["foon"]).fu_count


# --- a dot program that exits 0 without a picture ------------------------------------------


BROKEN_DOTS = {
    "silent": "cat >/dev/null",
    "garbage": "cat >/dev/null; echo garbage",
    "cut": 'cat >/dev/null; printf \'<?xml version="1.0"?>\\n<svg width="1">\\n\'',
    "wrong-kind": "cat >/dev/null; printf '<svg></svg>\\n'",
}


def broken_dot(tmp_path: Path, name: str) -> str:
    path = tmp_path / f"dot-{name}"
    path.write_text(f"#!/bin/sh\n{BROKEN_DOTS[name]}\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)


@pytest.mark.parametrize(
    ("name", "fmt"),
    [
        (name, fmt)
        for name in sorted(BROKEN_DOTS)
        for fmt in ("svg", "png", "pdf", "html")
        # An SVG is the right kind of output for svg and html.
        if not (name == "wrong-kind" and fmt in ("svg", "html"))
    ],
)
def test_a_dot_that_writes_no_picture_is_an_error(tmp_path: Path, name: str, fmt: str) -> None:
    env = {"FOON_DOT": broken_dot(tmp_path, name)}
    p = cli("plan", "--format", fmt, "-q", env=env)
    assert p.returncode == 1
    assert p.stdout == b""
    assert f"for -T{'svg' if fmt == 'html' else fmt}" in one_error_line(p)
    # --out: no file either.
    out = tmp_path / "out"
    p = cli("plan", "--format", fmt, "-q", "--out", str(out), env=env)
    assert p.returncode == 1
    assert not out.exists() or not any(out.iterdir())
    if fmt != "html":
        p = cli("draw", str(EXAMPLE["foon"]), "--format", fmt, env=env)
        assert p.returncode == 1 and p.stdout == b""
        one_error_line(p)


def test_a_dot_that_writes_no_picture_is_an_output_error_in_python(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    ex = foon.example()
    tree = ex.foon.planner(ex.kitchen, motions=ex.motions, utensils=ex.utensils).plan(
        ex.goals[0], "ids"
    )
    monkeypatch.setenv("FOON_DOT", broken_dot(tmp_path, "silent"))
    with pytest.raises(foon.OutputError, match="wrote nothing"):
        tree.to_svg()
    assert tree._repr_svg_() is None
    with pytest.raises(foon.OutputError, match="wrote nothing"):
        ex.foon.write("png")


# --- the size message of a picture names the command's own options -------------------------


def test_a_tree_picture_too_large_says_how_plan_narrows_it() -> None:
    p = cli("plan", "--goals", str(EXAMPLE["goals"]), "--format", "svg", "--max-nodes", "5")
    assert p.returncode == 1 and p.stdout == b""
    msg = one_error_line(p)
    # `foon plan` has no --depth (a usage error): it narrows by drawing fewer trees.
    assert "--out DIR" in msg and "--max-nodes" in msg
    assert "--depth" not in msg
    p = cli("draw", str(EXAMPLE["foon"]), "--max-nodes", "5")
    assert p.returncode == 1
    msg = one_error_line(p)
    assert "--goal" in msg and "--depth" in msg


# --- characters FOON text holds --------------------------------------------------------------

#: Control characters FOON text holds (all but NUL, the line feed and the TAB separator), C1
#: included, and characters XML cannot hold.
ODD = [chr(c) for c in range(1, 32) if chr(c) not in "\t\n"] + ["\x7f", "\x85", "\x9f"]
ODD += ["\ufffe", "\uffff", "\u2028", "\ufeff", "\u200b", '"', "\\", "<", "&", "{", "}"]
ODD_TEXT = st.text(st.sampled_from(ODD) | st.sampled_from("ab é"), min_size=1, max_size=6)


def odd_foon(label: str, state: str, ingredient: str, container: str, motion: str) -> str:
    # Fields start and end with a letter: text strips the ends of labels, states, motions.
    label, state, motion = (f"a{t}z" for t in (label, state, motion))
    ingredient = f"i{ingredient.replace(',', '')}z"
    return (
        f"//\nO\t{label}\nS\t{state}\nS\tcontains\t{{{ingredient}}}\nS\tin\t[c{container}z]\n"
        f"O\tknife\nM\t{motion}\t<{container}>\nO\t{label}\nS\tcut\n//\n"
    )


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(label=ODD_TEXT, state=ODD_TEXT, ingredient=ODD_TEXT, container=ODD_TEXT, motion=ODD_TEXT)
def test_what_text_loads_round_trips_through_json_and_validates(
    label: str, state: str, ingredient: str, container: str, motion: str
) -> None:
    """A FOON that loads from text is written as JSON that follows the schema and loads back
    to the same FOON (control characters included: the JSON loader refused them)."""
    f = foon.Foon.from_text(odd_foon(label, state, ingredient, container, motion))
    assert f.fu_count == 1
    doc = f.to_json()
    validate(json.loads(doc), "foon")
    back = foon.Foon.from_text(doc)
    assert back.to_json() == doc
    assert back.to_text() == f.to_text()
    assert [o.to_dict() for o in back.objects()] == [o.to_dict() for o in f.objects()]


def test_json_still_refuses_what_text_cannot_hold(tmp_path: Path) -> None:
    unit = '{{"input_nodes": [{{"label": "{}"}}], "motion_node": "m", "output_nodes": []}}'
    for bad in ("a\\u0000b", "a\\nb", "a\\tb"):
        p = tmp_path / "bad.json"
        p.write_text(f"[{unit.format(bad)}]")
        with pytest.raises(foon.ParseError, match="control character") as e:
            foon.load(p)
        # At the label's value (the column where the parser read it).
        assert e.value.path == str(p) and e.value.line == 1
        assert e.value.column is not None and 29 <= e.value.column <= 40


@pytest.mark.parametrize("ch", ["\ufffe", "\uffff", "\x1b", "\x7f"])
def test_svg_is_xml_and_graphml_says_what_it_cannot_hold(tmp_path: Path, ch: str) -> None:
    path = tmp_path / "odd.txt"
    path.write_text(odd_foon(ch, "raw", "x", "pot", "cut"), encoding="utf-8")
    f = foon.load(path)
    dot = f.to_dot()
    assert "\ufffe" not in dot and "\uffff" not in dot
    bad_for_xml = ch in "\ufffe\uffff\x1b"
    p = cli("export", str(path), "--format", "graphml")
    if bad_for_xml:
        # An output the writer cannot make: one error line, exit 1, no usage line.
        with pytest.raises(foon.OutputError, match="cannot hold"):
            f.write("graphml")
        assert p.returncode == 1 and p.stdout == b""
        assert "cannot hold" in one_error_line(p)
        assert b"usage:" not in p.stderr
    else:
        assert p.returncode == 0
        ET.fromstring(p.stdout)
    need_program("dot")
    svg = str(f.write("svg"))
    ET.fromstring(svg.encode())  # well-formed XML whatever the label holds
    p = cli("draw", str(path))
    assert p.returncode == 0, p.stderr.decode()
    ET.fromstring(p.stdout)


# --- -o onto a device or a pipe ------------------------------------------------------------


def _fifo_reader(path: Path) -> int:
    """A reader of the FIFO ``path``, opened without waiting, so that a writer never blocks
    (and a command that replaced the FIFO instead of writing into it never hangs the test)."""
    os.mkfifo(path)
    return os.open(path, os.O_RDONLY | os.O_NONBLOCK)


def _drain(fd: int) -> bytes:
    out = b""
    while True:
        try:
            chunk = os.read(fd, 1 << 16)
        except BlockingIOError:
            return out
        if not chunk:
            return out
        out += chunk


@pytest.mark.parametrize("through_link", [False, True])
def test_dash_o_onto_a_pipe_writes_into_it(tmp_path: Path, through_link: bool) -> None:
    """``-o /dev/stdout`` or ``-o /dev/null`` wrote a temporary file and renamed it over the
    device, replacing it with a regular file. A FIFO stands in for the device here."""
    fifo = tmp_path / "pipe"
    fd = _fifo_reader(fifo)
    dest = fifo
    if through_link:
        dest = tmp_path / "link"
        dest.symlink_to(fifo)
    try:
        p = cli("export", str(EXAMPLE["foon"]), "--format", "text", "-o", str(dest))
        assert p.returncode == 0, p.stderr.decode()
        assert stat.S_ISFIFO(os.stat(dest).st_mode) and stat.S_ISFIFO(os.lstat(fifo).st_mode)
        assert through_link == os.path.islink(dest)
        assert _drain(fd).decode() == foon.load(EXAMPLE["foon"]).to_text()
    finally:
        os.close(fd)


def test_out_dir_refuses_a_pipe_in_the_way(tmp_path: Path) -> None:
    out = tmp_path / "trees"
    out.mkdir()
    fd = _fifo_reader(out / "ice.txt")  # the example goal's file name
    try:
        p = cli("plan", "--out", str(out), "-q")
        assert p.returncode == 1
        assert "not a regular file" in one_error_line(p)
        assert stat.S_ISFIFO(os.lstat(out / "ice.txt").st_mode)
        assert sorted(x.name for x in out.iterdir()) == ["ice.txt"]
    finally:
        os.close(fd)
