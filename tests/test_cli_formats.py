"""The command line's output formats: `foon plan --format`, `--out DIR` with each format's
extension, `foon export` and `foon draw`, through the core's one writer interface. (What
each format contains is tested in its own file; here: the plumbing, the file names, the
errors and that nothing partial is written.)"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import foon
import pytest
from conftest import DATA, need_program, need_shared

TREE_FORMATS = [n for n, f in foon.FORMATS.items() if f[4]]
FOON_FORMATS = [n for n, f in foon.FORMATS.items() if f[5]]

SIGNATURES = {
    "svg": b"<?xml",
    "png": b"\x89PNG\r\n\x1a\n",
    "pdf": b"%PDF",
    "html": b"<!DOCTYPE html>",
    "dot": b"digraph",
    "graphml": b"<?xml",
    "json": b"",
    "text": b"//",
    "steps": b"1. ",
    "pddl": b"",
}


def cli(*argv: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run(
        [sys.executable, "-m", "foon", *argv],
        capture_output=True,
        check=False,
        env={**os.environ, **(env or {})},
        timeout=300,
    )


def test_the_format_table_comes_from_the_core() -> None:
    assert set(SIGNATURES) <= set(foon.FORMATS) | {"text"}
    for name, (ext, mime, binary, *_) in foon.FORMATS.items():
        assert ext.startswith(".") and "/" in mime
        assert binary == (name in ("png", "pdf"))


@pytest.mark.parametrize("fmt", TREE_FORMATS)
def test_plan_writes_every_tree_format_on_the_example(fmt: str) -> None:
    if foon.FORMATS[fmt][3]:
        need_program("dot")
    p = cli("plan", "--format", fmt, "-q")
    assert p.returncode == 0, p.stderr.decode()
    assert p.stdout.startswith(SIGNATURES[fmt]), p.stdout[:80]
    if fmt == "json":
        (tree,) = json.loads(p.stdout)
        assert tree["solved"] and tree["units"]
    if fmt == "steps":
        lines = p.stdout.decode().splitlines()
        assert [ln.split(".")[0] for ln in lines] == [str(i + 1) for i in range(len(lines))]


@pytest.mark.parametrize("fmt", ["dot", "svg", "png", "steps", "json", "graphml"])
def test_out_dir_writes_one_file_per_goal_with_the_format_extension(
    fmt: str, tmp_path: Path
) -> None:
    if foon.FORMATS[fmt][3]:
        need_program("dot")
    goals = foon.example().paths["goals"]
    out = tmp_path / "trees"
    p = cli("plan", "--goals", str(goals), "--format", fmt, "--out", str(out), "-q")
    ext = foon.FORMATS[fmt][0]
    files = sorted(out.iterdir())
    assert files and all(f.suffix == ext for f in files)
    solved = p.stderr.decode().count("FAILED")
    assert len(files) == len(foon.load_goals(goals)) - solved
    for f in files:
        assert f.read_bytes().startswith(SIGNATURES[fmt])
        if fmt == "json":
            assert isinstance(json.loads(f.read_bytes()), dict)


def test_several_goals_in_one_picture_have_a_cluster_each() -> None:
    goals = foon.load_goals(foon.example().paths["goals"])
    p = cli("plan", "--goals", str(foon.example().paths["goals"]), "--format", "dot", "-q")
    text = p.stdout.decode()
    # Every planned goal has its cluster (an unsolved one shows its goal alone).
    assert text.count("subgraph cluster_") == len(goals)
    assert text.count("digraph") == 1


def test_pddl_of_several_goals_to_stdout_is_refused_before_any_output() -> None:
    p = cli("plan", "--goals", str(foon.example().paths["goals"]), "--format", "pddl")
    assert p.returncode == 2  # a usage error: the command's usage, then why
    assert p.stdout == b""
    err = p.stderr.decode().strip().splitlines()
    assert err[0].startswith("usage: foon plan") and "Traceback" not in p.stderr.decode()
    assert err[-1] == "foon: error: PDDL holds one goal's problem: give one goal or --out DIR"


def test_missing_graphviz_is_one_clear_line_and_dot_still_works(tmp_path: Path) -> None:
    env = {"FOON_DOT": str(tmp_path / "no-such-dot")}
    p = cli("plan", "--format", "svg", env=env)
    assert p.returncode == 1 and p.stdout == b""
    (line,) = [ln for ln in p.stderr.decode().splitlines() if ln.startswith("foon: error")]
    assert "apt-get install graphviz" in line and "--format dot" in line
    out = tmp_path / "trees"
    p = cli("plan", "--format", "png", "--out", str(out), env=env)
    assert p.returncode == 1 and not out.exists()
    p = cli("plan", "--format", "dot", env=env)
    assert p.returncode == 0 and p.stdout.startswith(b"digraph")


@pytest.mark.parametrize("fmt", [f for f in FOON_FORMATS if f != "pddl"])
def test_export_writes_a_foon_in_every_format(fmt: str, tmp_path: Path) -> None:
    if foon.FORMATS[fmt][3]:
        need_program("dot")
    ex = foon.example()
    dest = tmp_path / ("out" + foon.FORMATS[fmt][0])
    p = cli("export", str(ex.paths["foon"]), "--format", fmt, "-o", str(dest))
    assert p.returncode == 0, p.stderr.decode()
    assert dest.read_bytes().startswith(SIGNATURES[fmt])
    p2 = cli("export", str(ex.paths["foon"]), "--format", fmt)
    if fmt not in ("svg", "png", "pdf"):  # Graphviz stamps nothing, but keep it to text
        assert p2.stdout == dest.read_bytes()


def test_export_pddl_needs_a_goal() -> None:
    ex = foon.example()
    p = cli("export", str(ex.paths["foon"]), "--format", "pddl")
    assert p.returncode != 0 and p.stdout == b""
    assert "goal" in p.stderr.decode() and "Traceback" not in p.stderr.decode()
    g = json.dumps(ex.goals[0].to_dict())
    p = cli(
        "export",
        str(ex.paths["foon"]),
        "--format",
        "pddl",
        "--goal",
        g,
        "--kitchen",
        str(ex.paths["kitchen"]),
        "--utensils",
        str(ex.paths["utensils"]),
    )
    assert p.returncode == 0, p.stderr.decode()
    assert b"(define" in p.stdout


def test_draw_a_neighbourhood_and_refuse_the_whole_course_foon(tmp_path: Path) -> None:
    need_shared()
    need_program("dot")
    dest = tmp_path / "salad.svg"
    p = cli("draw", str(DATA / "FOON.txt"), "--label", "greek salad", "-o", str(dest))
    assert p.returncode == 0, p.stderr.decode()
    assert dest.read_bytes().startswith(b"<?xml") and b"greek salad" in dest.read_bytes()
    big = tmp_path / "all.svg"
    p = cli("draw", str(DATA / "FOON.txt"), "-o", str(big))
    assert p.returncode == 1 and not big.exists()
    msg = p.stderr.decode()
    assert "--goal" in msg and "--depth" in msg and "--max-nodes" in msg


def test_draw_depth_without_a_goal_is_a_usage_error() -> None:
    p = cli("draw", str(foon.example().paths["foon"]), "--depth", "2")
    assert p.returncode == 2 and "--depth needs --goal" in p.stderr.decode()


def test_export_to_a_folder_name_is_refused(tmp_path: Path) -> None:
    p = cli("export", str(foon.example().paths["foon"]), "--format", "dot", "-o", f"{tmp_path}/")
    assert p.returncode == 2 and "names a folder" in p.stderr.decode()


def test_export_never_overwrites_its_input(tmp_path: Path) -> None:
    src = tmp_path / "f.foon"
    src.write_bytes(foon.example().paths["foon"].read_bytes())
    before = src.read_bytes()
    p = cli("export", str(src), "--format", "text", "-o", str(src))
    assert p.returncode == 1 and src.read_bytes() == before


@pytest.mark.parametrize("fmt", ["dot", "steps", "graphml", "pddl", "text"])
def test_an_unsolved_single_goal_writes_no_document(fmt: str) -> None:
    ex = foon.example()
    goals = foon.load_goals(ex.paths["goals"])
    trees = ex.foon.plan_many(goals, ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    unsolved = next(g for g, t in zip(goals, trees, strict=True) if not t.solved)
    p = cli("plan", "--goal", json.dumps(unsolved.to_dict()), "--format", fmt)
    assert p.returncode == 1 and p.stdout == b""
    assert "FAILED" in p.stderr.decode()


def test_compare_writes_every_comparison_format() -> None:
    ex = foon.example()
    base = ["compare", "--goals", str(ex.paths["goals"]), "--methods", "ids,optimal-units"]
    outs = {}
    for fmt in [n for n, f in foon.FORMATS.items() if f[6]]:
        if foon.FORMATS[fmt][3]:
            need_program("dot")
        p = cli(*base, "--format", fmt)
        assert p.returncode == 0, p.stderr.decode()
        outs[fmt] = p.stdout
    assert outs["html"].startswith(b"<!DOCTYPE html>") and b"optimal-units" in outs["html"]
    rows = json.loads(outs["json"])["rows"]
    assert len(rows) == 2 * len(foon.load_goals(ex.paths["goals"]))

    # --json and --csv are the same as --format json|csv (the timings aside).
    def untimed(data: bytes) -> object:
        d = json.loads(data)
        for r in d["rows"]:
            r.pop("seconds")
        for r in d["summary"]:
            r.pop("seconds_total")
        return d

    assert untimed(cli(*base, "--json").stdout) == untimed(outs["json"])
    csv_alias = cli(*base, "--csv").stdout.splitlines()
    assert csv_alias[0] == outs["csv"].splitlines()[0]
    assert len(csv_alias) == len(outs["csv"].splitlines())
    assert outs["text"].decode().splitlines()[0].split()[:2] == ["goal", "method"]


def test_depth_without_a_goal_is_refused_in_python_too() -> None:
    with pytest.raises(ValueError, match="depth needs a goal"):
        foon.example().foon.write("dot", depth=1)
