"""The TextMate grammar: valid, generated from the Lark grammar, and with the Lark grammar's keywords."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from vkgl.editor import textmate
from vkgl.editor.vocabulary import keywords

REPO = Path(__file__).resolve().parents[2]
VSCODE = REPO / "editors" / "vscode"
GRAMMAR = VSCODE / "syntaxes" / "vkg.tmLanguage.json"


def load(path: Path) -> Any:
    return json.loads(path.read_text(encoding="utf-8"))


def rules(grammar: dict[str, Any]) -> list[dict[str, Any]]:
    """Every rule of the grammar: top-level patterns and repository entries."""
    return [*grammar["patterns"], *grammar["repository"].values()]


def test_the_grammar_keywords_equal_the_lark_grammars() -> None:
    lark_words = set(re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)"', (REPO / "grammar" / "vkg.lark").read_text()))
    assert textmate.keywords_of(load(GRAMMAR)) == sorted(lark_words) == list(keywords())


def test_the_committed_grammar_is_the_generated_one() -> None:
    assert textmate.check(GRAMMAR) == [], "run `python -m vkgl.editor.textmate`"


def test_a_stale_grammar_is_reported(tmp_path: Path) -> None:
    stale = load(GRAMMAR)
    stale["repository"]["keywords"]["match"] = stale["repository"]["keywords"]["match"].replace("|goal", "")
    path = tmp_path / "vkg.tmLanguage.json"
    path.write_text(json.dumps(stale), encoding="utf-8")
    assert textmate.check(path) and textmate.main(["--check", "-o", str(path)]) == 1
    assert "goal" not in textmate.keywords_of(stale)


def test_the_grammar_is_a_valid_textmate_grammar() -> None:
    grammar = load(GRAMMAR)
    assert grammar["scopeName"] == "source.vkg" and grammar["fileTypes"] == ["vkg"]
    for rule in grammar["patterns"]:
        assert set(rule) == {"include"} and rule["include"][1:] in grammar["repository"]
    for name, rule in grammar["repository"].items():
        assert "match" in rule, name
        pattern = re.compile(rule["match"])  # TextMate uses Oniguruma; these patterns are in the common subset
        assert "name" in rule or "captures" in rule, name
        scopes = [rule.get("name")] + [c["name"] for c in rule.get("captures", {}).values()]
        assert all(s is None or s.endswith(".vkg") for s in scopes), name
        assert all(int(group) <= pattern.groups for group in rule.get("captures", {})), name


@pytest.mark.parametrize(
    ("text", "rule"),
    [
        ("# a comment", "comment"),
        ('"panda.urdf"', "string"),
        ("use stdlib.bodies.block", "use"),
        ("body Block", "declaration"),
        ("block : Block", "instance"),
        ("prismatic", "types"),
        ("goal", "keywords"),
        ("+x", "face"),
        ("10 cm", "quantity"),
        (") m", "vector-unit"),
    ],
)
def test_each_rule_matches_what_it_is_for(text: str, rule: str) -> None:
    assert re.fullmatch(load(GRAMMAR)["repository"][rule]["match"], text)


def test_the_extension_manifest_wires_the_language_grammar_and_server() -> None:
    manifest = load(VSCODE / "package.json")
    language = manifest["contributes"]["languages"][0]
    assert language["id"] == "vkg" and language["extensions"] == [".vkg"]
    assert (VSCODE / language["configuration"]).is_file()
    grammar = manifest["contributes"]["grammars"][0]
    assert grammar["scopeName"] == "source.vkg" and (VSCODE / grammar["path"]).resolve() == GRAMMAR
    assert manifest["contributes"]["configuration"]["properties"]["vkg.server.command"]["default"] == ["vkgc", "lsp"]
    assert (VSCODE / manifest["main"]).is_file() and "vscode-languageclient" in manifest["dependencies"]
    config = load(VSCODE / "language-configuration.json")
    assert config["comments"] == {"lineComment": "#"}
    assert ["{", "}"] in config["brackets"] and ["(", ")"] in config["brackets"]
