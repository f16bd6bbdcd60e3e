"""The lab's two annotations of the same 111 recipes, ``subgraphs_sakib_JSON/*.json`` and
``subgraphs_sakib_TXT/*.txt``, load to the same functional units, except for the real
differences between the two annotations, listed below one by one."""

from __future__ import annotations

import warnings
from pathlib import Path

import foon
import pytest
from conftest import DATA, need_shared

Key = tuple[str, tuple[str, ...], tuple[str, ...]]


def load(p: Path) -> foon.Foon:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        return foon.load(p)


def keys(f: foon.Foon) -> dict[Key, int]:
    """Each unit by its identity (motion, multisets of inputs and of outputs), objects given
    by their one-line form with sorted states and ingredients."""

    def obj(o: foon.Object) -> str:
        label, states, ingredients, container = o.identity()
        return str(foon.Object(label, states, ingredients, container))

    out = {}
    for i in range(f.fu_count):
        u = f.fu(i)
        out[(u.motion, tuple(sorted(map(obj, u.inputs))), tuple(sorted(map(obj, u.outputs))))] = i
    return out


# The real differences between the two annotations: per recipe, the units only the JSON has
# and the units only the text has (motion, inputs, outputs).
DIFFERENCES: dict[str, tuple[list[Key], list[Key]]] = {
    # The JSON has one more unit: the patty placed on the plate (the text goes on without it).
    "0032-cheeseburger": (
        [
            (
                "place",
                (
                    "garlic (minced) in [patty]",
                    "onion (minced) in [patty]",
                    "patty (raw) {ground beef} in [hand]",
                    "plate (empty)",
                ),
                (
                    "garlic (minced) in [patty]",
                    "onion (minced) in [patty]",
                    "patty (raw) {garlic,ground beef,onion} in [hand]",
                    "patty (raw) {garlic,ground beef,onion} in [hand]",
                    "patty (raw) {garlic,ground beef,onion} in [plate]",
                    "plate {patty}",
                ),
            )
        ],
        [],
    ),
    # The text turns the stove "off"; the JSON leaves the stove without a state.
    "0064-goat_cheese_frittata-mahalo": (
        [
            ("turn off", ("stove (on) in [frying pan]",), ("stove in [frying pan]",)),
            (
                "insert",
                (
                    (
                        "frying pan (hot) {basil,butter,egg,goat cheese,olive oil,onion,sweet pepper,tomato,"
                        "zucchini} in [stove]"
                    ),
                    "oven (empty, on)",
                    "stove in [frying pan]",
                ),
                (
                    (
                        "frying pan (hot) {basil,butter,egg,goat cheese,olive oil,onion,sweet pepper,tomato,"
                        "zucchini} in [oven]"
                    ),
                    "oven (on) {frying pan}",
                    "stove",
                ),
            ),
        ],
        [
            ("turn off", ("stove (on) in [frying pan]",), ("stove (off) in [frying pan]",)),
            (
                "insert",
                (
                    (
                        "frying pan (hot) {basil,butter,egg,goat cheese,olive oil,onion,sweet pepper,tomato,"
                        "zucchini} in [stove]"
                    ),
                    "oven (empty, on)",
                    "stove (off) in [frying pan]",
                ),
                (
                    (
                        "frying pan (hot) {basil,butter,egg,goat cheese,olive oil,onion,sweet pepper,tomato,"
                        "zucchini} in [oven]"
                    ),
                    "oven (on) {frying pan}",
                    "stove (off)",
                ),
            ),
        ],
    ),
    # One pour differs: the JSON adds an empty bowl, an uncracked egg and a second copy of
    # the egg white and yolk to the inputs, and the bowl to the outputs.
    "0083-pastel-fried_savory_pastry": (
        [
            (
                "pour",
                (
                    "bowl (empty)",
                    "bowl {egg white and yolk}",
                    "container {garlic powder,garlic powder,olive oil,salt}",
                    "egg (uncracked)",
                    "egg white and yolk in [bowl]",
                    "egg white and yolk in [bowl]",
                ),
                (
                    "bowl {egg white and yolk}",
                    "container {egg white and yolk,garlic powder,garlic powder,olive oil,salt}",
                    "egg white and yolk in [container]",
                ),
            )
        ],
        [
            (
                "pour",
                (
                    "bowl {egg white and yolk}",
                    "container {garlic powder,garlic powder,olive oil,salt}",
                    "egg white and yolk in [bowl]",
                ),
                (
                    "container {egg white and yolk,garlic powder,garlic powder,olive oil,salt}",
                    "egg white and yolk in [container]",
                ),
            )
        ],
    ),
}


def recipes() -> list[str]:
    return sorted(p.stem for p in (DATA / "subgraphs_sakib_JSON").glob("*.json"))


def test_both_annotations_hold_the_same_recipes() -> None:
    need_shared()
    txt = sorted(p.stem for p in (DATA / "subgraphs_sakib_TXT").glob("*.txt"))
    assert recipes() == txt and len(txt) > 100
    assert set(DIFFERENCES) <= set(txt)


@pytest.mark.parametrize("name", recipes() if (DATA / "subgraphs_sakib_JSON").is_dir() else [])
def test_json_recipe_has_the_units_of_the_text_recipe(name: str) -> None:
    j = load(DATA / "subgraphs_sakib_JSON" / f"{name}.json")
    t = load(DATA / "subgraphs_sakib_TXT" / f"{name}.txt")
    kj, kt = keys(j), keys(t)
    only_json, only_text = DIFFERENCES.get(name, ([], []))
    assert sorted(kj.keys() - kt.keys()) == sorted(only_json)
    assert sorted(kt.keys() - kj.keys()) == sorted(only_text)
    # Where the units agree, so does their order (both files list a recipe in its order).
    common = [k for k in kt if k in kj]
    assert [kj[k] for k in common] == sorted(kj[k] for k in common)
    # Identical recipes are identical FOONs in the course text form too.
    if not only_json and not only_text:
        assert j.to_text() == t.to_text()
        assert j.stats()["objects"] == t.stats()["objects"]
