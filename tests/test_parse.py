"""Parsing: the four dialects, normalisation, identity, duplicates, warnings, writing back."""

from __future__ import annotations

import foon
import pytest

A = "O\tonion\nS\twhole\nO\tknife\nM\tchop\nO\tonion\nS\tchopped\nO\tknife\n//\n"
A_IDS = "O1\tonion\nS1\twhole\nO1\tknife\nM1\tchop\nO1\tonion\nS1\tchopped\nO1\tknife\n//\n"
B = (
    "# Source:\thttp://example.org/v.mp4\r\n//\r\n"
    "O12\tOnion\t1\r\nS3\twhole\r\nO7\tknife\t0\r\nM4\tchop\t1:10\t1:11\r\n"
    "O12\tonion\t1\r\nS5\tchopped\r\nO7\tknife\t0\r\n//\r\n"
)
B_PRIME = (
    "O\tonion\t1\nS\twhole\nO\tknife\t0\nM\tchop\t<1:10,1:11>\n"
    "O\tonion\t1\nS\tchopped\nO\tknife\t0\n//\n"
)


@pytest.mark.parametrize("text", [A, A_IDS, B, B_PRIME], ids=["A", "A'", "B", "B'"])
def test_every_dialect_gives_the_same_graph(text: str) -> None:
    f = foon.Foon.from_text(text)
    assert f.fu_count == 1
    assert [str(f.object(i)) for i in range(f.object_count)] == [
        "onion (whole)",
        "knife",
        "onion (chopped)",
    ]
    fu = f.fu(0)
    assert fu.motion == "chop"
    assert fu.input_ids == (0, 1) and fu.output_ids == (2, 1)
    # The bare knife output is not indexed as produced (course rule).
    assert f.producers(1) == [] and f.producers(2) == [0]
    assert f.consumers(0) == [0]


def test_normalisation_and_identity() -> None:
    text = (
        "O\tBowl  \nS\tcontains\t{jelly, peanut butter}\nS\tEmpty\nS\thot\n"
        "O\tbread\nS\tin\t[bowl]  \nS\ton\nM\tMix \n"
        "O\tbowl\nS\thot\nS\tempty\nS\twith\t{ peanut butter,jelly}\n//\n"
    )
    f = foon.Foon.from_text(text)
    # Label and states lower-cased and right-stripped; ingredients kept as written (the
    # space before "peanut butter" stays), relation words ignored, "S\ton" is a state.
    assert f.object(0) == foon.Object("bowl", ("empty", "hot"), ("jelly", " peanut butter"))
    assert f.object(1) == foon.Object("bread", ("on",), (), "bowl")
    assert f.fu(0).motion == "mix"
    # The output bowl has the same label and multisets in another order: the same object.
    assert f.object_count == 2
    assert f.fu(0).output_ids == (0,)
    assert f.find(foon.Object("bowl", ("hot", "empty"), (" peanut butter", "jelly"))) == 0
    assert f.find(foon.Object("bowl", ("hot", "empty"), ("peanut butter", "jelly"))) is None


def test_duplicates_inside_lists_are_kept() -> None:
    f = foon.Foon.from_text(
        "O\ta\nS\tx\nS\tx\nM\tm\nO\tb\nS\ty\n//\nO\ta\nS\tx\nM\tm\nO\tb\nS\tz\n//\n"
    )
    assert f.object(0).states == ("x", "x")
    assert f.object_count == 4  # a(x,x), b(y), a(x), b(z)


def test_duplicate_units_are_dropped_and_counted() -> None:
    fu1 = "O\ta\nS\tx\nO\tk\nM\tm\nO\tb\nS\ty\n//\n"
    swapped = "O\tk\nO\ta\nS\tx\nM\tm\nO\tb\nS\ty\n//\n"
    f = foon.Foon.from_text(fu1 + swapped + fu1)
    assert f.fu_count == 1
    assert f.stats()["duplicates_dropped"] == 2


def test_warnings_name_the_line_and_strict_mode_raises() -> None:
    text = (
        "O\ta\nS\tx\nO\tb\nS\ty\n//\n"  # no motion: warning at line 5
        "O\ta\nS\tx\nM\tm\nO\tb\nM\tn\nO\tc\n//\n"  # two motions: warning at line 10
        "O\ta\nS\tx\nM\tm\nO\tb\nS\ty\n"
    )  # unterminated: warning at line 17
    with pytest.warns(foon.FoonWarning) as rec:
        f = foon.Foon.from_text(text, path="t.foon")
    assert [str(w.message) for w in rec] == [
        "t.foon:5:1: functional unit starting at line 1 has no motion line; it is dropped [no-motion]",
        "t.foon:10:1: functional unit starting at line 6 has a second motion line; it is dropped [two-motions]",
        "t.foon:17:1: the last functional unit has no closing '//'; it is kept [unterminated]",
    ]
    assert f.fu_count == 1
    assert [(w[1], w[3]) for w in f.warnings] == [
        (5, "no-motion"),
        (10, "two-motions"),
        (17, "unterminated"),
    ]
    with pytest.raises(foon.ParseError, match=r"t.foon:5:1: .*no motion line.*strict mode"):
        foon.Foon.from_text(text, path="t.foon", strict=True)


def test_comments_blank_lines_and_empty_trailing_fields() -> None:
    f = foon.Foon.from_text("# header\n//\n\nO\tlamp\nS\toff\t\nM\tswitch\t\nO\tlamp\nS\ton\n//\n")
    assert str(f.object(0)) == "lamp (off)"
    assert f.fu(0).motion == "switch"


def test_write_back_keeps_each_units_own_order() -> None:
    text = (
        "O\tbowl\nS\tcold\nS\tempty\nM\tm\nO\tbowl\nS\tx\n//\n"
        "O\tbowl\nS\tempty\nS\tcold\nS\tcontains\t{b,a}\nS\tin\t[sink]\nM\tn\nO\tbowl\nS\ty\n//\n"
    )
    f = foon.Foon.from_text(text)
    assert f.fu_text(0) == "O\tbowl\nS\tcold\nS\tempty\nM\tm\nO\tbowl\nS\tx\n//"
    assert f.fu_text(1) == (
        "O\tbowl\nS\tempty\nS\tcold\nS\tcontains\t{b,a}\nS\tin\t[sink]\nM\tn\nO\tbowl\nS\ty\n//"
    )
    again = foon.Foon.from_text(f.to_text())
    assert again.fu_count == f.fu_count and again.object_count == f.object_count
    assert again.to_text() == f.to_text()


def test_round_trip_of_the_course_foon(course: object) -> None:
    from conftest import DATA

    f = foon.load(DATA / "FOON.txt")
    g = foon.Foon.from_text(f.to_text())
    assert g.stats() == f.stats() | {"index_bytes": g.stats()["index_bytes"]}
    assert g.to_text() == f.to_text()


@pytest.mark.parametrize(
    ("text", "line", "column", "reason"),
    [
        ("X\tonion\n", 1, 1, "unknown line kind"),
        ("//\nS\twhole\n", 2, 1, "state line before any object"),
        ("O\n", 1, 2, "missing object label"),
        ("O\t  \n", 1, 3, "empty object label"),
        ("O\tbowl\nS\tin\tcup\n", 2, 6, "expected '{ingredients}' or '[container]'"),
        ("O\tbowl\nS\tin\t[cup\n", 2, 6, "no closing ']'"),
        ("O\tbowl\nS\tcontains\t{a,b\n", 2, 12, "no closing '}'"),
        ("O\tb\xc3\xa9\xffl\n", 1, 5, "invalid UTF-8"),
        ("O\tbo\x00wl\n", 1, 5, "NUL byte"),
    ],
)
def test_errors_name_line_and_column(text: str, line: int, column: int, reason: str) -> None:
    data = text.encode("latin-1")  # the UTF-8 case is spelled as raw bytes above
    with pytest.raises(foon.ParseError) as e:
        foon.Foon.from_text(data, path="bad.foon")
    err = e.value
    assert (err.line, err.column) == (line, column)  # type: ignore[attr-defined]
    assert reason in err.reason  # type: ignore[attr-defined]
    assert err.path == "bad.foon"  # type: ignore[attr-defined]
    assert str(err).startswith(f"bad.foon:{line}:{column}: FOON error: ")
