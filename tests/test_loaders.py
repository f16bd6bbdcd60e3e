"""The core's loaders seen from Python: one object loader for files and command-line text,
rate tables with a repeated motion, utensil lists that are not, conflicting annotations,
strict-mode messages and the verifier's unit look-up."""

from __future__ import annotations

from pathlib import Path

import foon
import foon.cli
import pytest
from foon import _foon

TINY = "O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\n//\n"


@pytest.mark.parametrize(
    ("text", "column", "reason"),
    [
        ('{"label": "ice", "container": 5}', 31, "invalid type: integer `5`, expected a string"),
        ('{"label": "ice", "states": [1]}', 29, "invalid type: integer `1`, expected a string"),
        ('{"label": "ice", "states": 5}', 28, "invalid type: integer `5`, expected a sequence"),
        (
            '{"label": "ice", "states": "crushed"}',
            36,
            'invalid type: string "crushed", expected a sequence',
        ),
        ('{"label": null}', 14, "invalid type: null, expected a string"),
        ('{"label": "ice", "states": [NaN]}', 29, "expected value"),
        ('{"label": "ice", "colour": "red"}', 25, "unknown field `colour`"),
        ("[" * 50_000 + "]" * 50_000, 1, "invalid type: sequence, expected struct ObjectSpec"),
    ],
    ids=[
        "container-5",
        "state-1",
        "states-5",
        "states-string",
        "label-null",
        "nan",
        "unknown",
        "deep",
    ],
)
def test_goal_text_has_the_file_loaders_errors(text: str, column: int, reason: str) -> None:
    # The same loader for --goal text and goal files: a typed error with a location.
    with pytest.raises(foon.ParseError) as info:
        _foon.parse_objects(text, "goal", "--goal")
    e = info.value
    assert (e.path, e.line, e.column) == ("--goal", 1, column)
    assert e.reason.startswith(reason), e.reason
    assert str(e).startswith(f"--goal:1:{column}: goal error: ")


def test_null_lists_are_empty_and_a_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    one = '{"label": "ice", "states": ["crushed"], "ingredients": null, "container": null}'
    assert _foon.parse_objects(one, "goal") == [("ice", ["crushed"], [], None)]
    path = tmp_path / "kitchen.json"
    path.write_bytes(b"\xef\xbb\xbf[" + one.encode() + b"]\n")
    assert foon.Kitchen.load(path).items == (foon.Object("ice", ("crushed",)),)
    assert _foon.load_objects(str(path), "goal") == [("ice", ["crushed"], [], None)]


def test_a_motion_with_two_rates_is_a_parse_error() -> None:
    with pytest.raises(foon.ParseError) as info:
        foon.MotionRates.from_text("pour\t0.8\nchop\t0.5\npour\t0.8\npour\t0.6\n")
    e = info.value
    assert (e.line, e.column) == (4, 6)
    assert e.reason == "motion 'pour' has two rates: 0.8 (line 1) and 0.6 (line 4)"
    assert dict(foon.MotionRates.from_text("pour\t0.8\npour\t0.80\n")) == {"pour": 0.8}


def test_a_kitchen_file_is_not_a_utensil_list(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    kitchen = tmp_path / "kitchen.json"
    kitchen.write_text('[\n  {"label": "bowl"}\n]\n')
    with pytest.raises(foon.ParseError) as info:
        foon.load_utensils(kitchen)
    assert (info.value.line, info.value.column) == (1, 1)
    assert "looks like JSON" in info.value.reason
    tiny = tmp_path / "tiny.foon"
    tiny.write_text(TINY)
    rc = foon.cli.main(
        [
            "plan",
            "--foon",
            str(tiny),
            "--utensils",
            str(kitchen),
            "--goal",
            '{"label": "onion", "states": ["chopped"]}',
        ]
    )
    err = capsys.readouterr().err
    assert rc == 1
    assert err.startswith(f"foon: error: {kitchen}:1:1: ") and len(err.splitlines()) == 1, err


CONFLICTS = [
    (
        "O\tonion\nS\tin\t[bowl]\nS\tin\t[pan]\nM\tfry\nO\tonion\nS\tfried\n//\n",
        "two-containers",
        3,
        6,
        "object 'onion' has a second container: [pan] after [bowl]",
    ),
    (
        "O\tbowl\nS\tcontains\t{a,b}\nS\tcontains\t{c}\nM\tmix\nO\tbowl\nS\tmixed\n//\n",
        "two-ingredient-lists",
        3,
        12,
        "object 'bowl' has a second ingredient list: {c} after {a,b}",
    ),
    (
        "O\tbowl\nS\tcontains\t{}\nM\tmix\nO\tbowl\nS\tmixed\n//\n",
        "empty-ingredient",
        2,
        13,
        "empty ingredient name in '{}'",
    ),
]


@pytest.mark.parametrize(
    ("text", "code", "line", "column", "fault"), CONFLICTS, ids=[c[1] for c in CONFLICTS]
)
def test_conflicting_annotations_are_findings_and_strict_errors(
    text: str, code: str, line: int, column: int, fault: str, tmp_path: Path
) -> None:
    path = tmp_path / "conflict.foon"
    path.write_text(text)
    f = foon.load(path)  # loads as the course does (the last one wins; '' is kept)
    assert f.fu_count == 1
    found = [x for x in foon.check(path) if x.code == code]
    assert [(x.line, x.column, x.severity) for x in found] == [(line, column, "warning")]
    assert found[0].message.startswith(fault)
    with pytest.raises(foon.ParseError) as info:
        foon.load(path, strict=True)
    e = info.value
    assert (e.line, e.column) == (line, column)
    assert e.reason == f"{fault} (strict mode)"


def test_the_last_annotation_wins_as_in_the_course() -> None:
    f = foon.Foon.from_text(CONFLICTS[0][0] + CONFLICTS[1][0] + CONFLICTS[2][0])
    assert f.object(0) == foon.Object("onion", (), (), "pan")
    assert f.object(2) == foon.Object("bowl", (), ("c",))
    assert f.object(4) == foon.Object("bowl", (), ("",))


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ("O\ta\nS\tx\n//\n", "functional unit starting at line 1 has no motion line"),
        (
            "O\ta\nM\tm\nM\tn\nO\tb\nS\ty\n//\n",
            "functional unit starting at line 1 has a second motion line",
        ),
        ("O\ta\nM\tm\nO\tb\nS\ty\n", "the last functional unit has no closing '//'"),
    ],
    ids=["no-motion", "two-motions", "unterminated"],
)
def test_strict_errors_do_not_read_as_warnings(text: str, fault: str) -> None:
    with pytest.raises(foon.ParseError) as info:
        foon.Foon.from_text(text, strict=True)
    assert info.value.reason == f"{fault} (strict mode)"


def test_verify_finds_a_unit_whose_first_output_is_bare(tmp_path: Path) -> None:
    # No inputs, and a first output with no state, ingredient or container.
    text = "M\ttake\nO\tknife\nO\tonion\nS\twhole\n//\n" + TINY
    tree = tmp_path / "tree.txt"
    tree.write_text(text)
    f = foon.Foon.from_text(text)
    r = f.verify(tree, foon.Object("onion", ("chopped",)))
    assert r.foreign_units == []
    assert r.valid
