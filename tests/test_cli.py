"""The command line: in-process through ``foon.cli.main`` and once through the installed
script."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import foon
import pytest
from foon.cli import main

Capture = pytest.CaptureFixture[str]


def run(argv: list[str], capsys: Capture) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_plan_without_arguments_prints_the_example_tree(capsys: Capture) -> None:
    code, out, err = run(["plan"], capsys)
    ex = foon.example()
    want = ex.foon.plan(
        ex.goals[0], ex.kitchen, "ids", motions=ex.motions, utensils=ex.utensils
    ).to_text()
    assert code == 0
    assert out == want and out.startswith("//\nO\t")
    assert "height" in err and "Traceback" not in err


def test_plan_json_has_the_documented_fields(capsys: Capture) -> None:
    code, out, _ = run(["plan", "--format", "json", "--method", "greedy-success"], capsys)
    assert code == 0
    [d] = json.loads(out)
    for key in (
        "goal",
        "method",
        "solved",
        "units",
        "fu_count",
        "height",
        "success",
        "leaf_inputs",
        "expanded",
        "seconds",
        "unresolved",
        "missing",
    ):
        assert key in d
    assert d["method"] == "greedy-success" and d["solved"] and d["fu_count"] == len(d["units"])


def test_all_example_goals_and_a_failure(capsys: Capture) -> None:
    ex = foon.example()
    code, out, err = run(["plan", "--goals", str(ex.paths["goals"])], capsys)
    assert code == 1  # the last example goal cannot be made
    assert out.count("# goal: ") == len(ex.goals)
    assert "FAILED (ids): missing from the kitchen: lemon (whole)" in err


def test_label_goal_and_ambiguous_label(capsys: Capture) -> None:
    code, out, err = run(["plan", "--label", "scrambled eggs"], capsys)
    assert code == 0 and out.startswith("//\n")
    code, out, err = run(["plan", "--label", "onion"], capsys)
    assert code == 1 and out == ""
    assert "matches" in err and "give the goal as JSON" in err
    assert "Traceback" not in err


def test_usage_errors_exit_2(capsys: Capture) -> None:
    code, _, err = run(["plan", "--method", "dfs"], capsys)
    assert code == 2 and err.startswith("usage: foon plan ") and "invalid choice" in err
    # An unknown option is reported by the command's parser too.
    code, _, err = run(["plan", "--bogus"], capsys)
    assert code == 2 and err.startswith("usage: foon plan ") and "--bogus" in err
    code, _, err = run(["plan", "--foon", str(foon.example().paths["foon"])], capsys)
    assert code == 2 and "give the goal" in err
    # The usage shown is the subcommand's, not the top-level one.
    assert err.startswith("usage: foon plan ") and "COMMAND" not in err


def test_bad_goal_json_is_one_error_line_from_the_core(capsys: Capture) -> None:
    code, out, err = run(["plan", "--goal", "{not json"], capsys)
    assert code == 1 and out == ""
    assert err.startswith("foon: error: --goal:1:2: ") and err.count("\n") == 1


def test_missing_and_bad_files_exit_1_without_traceback(tmp_path: Path, capsys: Capture) -> None:
    code, out, err = run(["plan", "--foon", str(tmp_path / "none.txt"), "--label", "x"], capsys)
    assert code == 1 and out == ""
    assert err.startswith("foon: error: ") and "none.txt" in err and "Traceback" not in err
    bad = tmp_path / "bad.txt"
    bad.write_text("O\tonion\nS\twhole\nZ\n")
    code, _, err = run(["stats", str(bad)], capsys)
    assert code == 1
    assert (
        err.strip()
        == f"foon: error: {bad}:3:1: FOON error: unknown line kind 'Z' (expected O, S, M, // or #, then a TAB)"
    )


def test_out_dir_writes_one_file_per_goal(tmp_path: Path, capsys: Capture) -> None:
    ex = foon.example()
    code, _, _ = run(
        [
            "plan",
            "--goals",
            str(ex.paths["goals"]),
            "--format",
            "json",
            "--out",
            str(tmp_path / "o"),
            "-q",
        ],
        capsys,
    )
    assert code == 1
    names = sorted(p.name for p in (tmp_path / "o").iterdir())
    # Two goals are labelled "tea"; the second (tea_2) cannot be made, so it has no file.
    assert names == ["ice.json", "onion.json", "salad.json", "scrambled_eggs.json", "tea.json"]
    d = json.loads((tmp_path / "o" / "ice.json").read_text())
    assert d["solved"] is True
    assert json.loads((tmp_path / "o" / "tea.json").read_text())["goal"]["ingredients"] == []


def test_out_never_replaces_an_input(tmp_path: Path, capsys: Capture) -> None:
    ex = foon.example()
    out = tmp_path / "o"
    out.mkdir()
    kitchen = out / "ice.txt"  # the name the default goal's tree would be written to
    kitchen.write_text(ex.paths["kitchen"].read_text())
    before = kitchen.read_bytes()
    code, _, err = run(
        [
            "plan",
            "--foon",
            str(ex.paths["foon"]),
            "--kitchen",
            str(kitchen),
            "--goal",
            json.dumps(ex.goals[0].to_dict()),
            "--out",
            str(out),
        ],
        capsys,
    )
    assert code == 1 and "refusing to overwrite an input file" in err
    assert kitchen.read_bytes() == before
    assert sorted(p.name for p in out.iterdir()) == ["ice.txt"]  # no temporary file left


def test_out_writes_nothing_when_a_later_goal_would_replace_an_input(
    tmp_path: Path, capsys: Capture
) -> None:
    ex = foon.example()
    first, second = ex.goals[0], next(g for g in ex.goals if g.label != ex.goals[0].label)
    out = tmp_path / "o"
    out.mkdir()
    kitchen = out / (second.label.replace(" ", "_") + ".txt")  # where the 2nd tree would go
    kitchen.write_text(ex.paths["kitchen"].read_text())
    before = kitchen.read_bytes()
    goals = json.dumps([first.to_dict(), second.to_dict()])
    code, _, err = run(["plan", "--foon", str(ex.paths["foon"]), "--kitchen", str(kitchen),
                        "--goal", goals, "--out", str(out)], capsys)  # fmt: skip
    assert code == 1 and "refusing to overwrite an input file" in err
    assert kitchen.read_bytes() == before
    assert sorted(p.name for p in out.iterdir()) == [kitchen.name]  # the first was not written


def test_out_file_names_stay_inside_the_folder(tmp_path: Path, capsys: Capture) -> None:
    text = "M\tmix\nO\t../evil\nS\tdone\n//\nM\tmix\nO\ta/b:c\nS\tdone\n//\n"
    (tmp_path / "f.txt").write_text(text)
    (tmp_path / "k.json").write_text("[]")
    goals = [
        {"label": "../evil", "states": ["done"], "ingredients": [], "container": None},
        {"label": "a/b:c", "states": ["done"], "ingredients": [], "container": None},
    ]
    out = tmp_path / "deep" / "o"
    code, _, err = run(["plan", "--foon", str(tmp_path / "f.txt"), "--kitchen",
                        str(tmp_path / "k.json"), "--goal", json.dumps(goals), "--method", "bfs",
                        "--out", str(out)], capsys)  # fmt: skip
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [".._evil.txt", "a_b_c.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deep", "f.txt", "k.json"]
    assert sorted(p.name for p in (tmp_path / "deep").iterdir()) == ["o"]


def test_stats_text_and_json(capsys: Capture) -> None:
    path = str(foon.example().paths["foon"])
    code, out, _ = run(["stats", path], capsys)
    assert code == 0 and "functional units" in out
    code, out, _ = run(["stats", "--json", path], capsys)
    [d] = json.loads(out)  # always a list, one object per file
    assert d["functional_units"] == foon.example().foon.fu_count and d["file"] == path
    code, out, _ = run(["stats", "--json", path, path], capsys)
    assert [d["file"] for d in json.loads(out)] == [path, path]


def test_installed_script_and_module_entry_point() -> None:
    script = shutil.which("foon") or str(Path(sys.executable).parent / "foon")
    p = subprocess.run(
        [script, "plan", "--method", "bfs", "--compat", "course"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("//\nO\t")
    m = subprocess.run(
        [sys.executable, "-m", "foon", "--version"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert m.returncode == 0 and m.stdout.strip() == f"foon {foon.__version__}"
