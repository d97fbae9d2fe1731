"""Issue 26: every command's --json output, on success and on a failure, validates against its JSON
Schema in docs/schemas/ (draft 2020-12), and follows the one vocabulary of docs/json.md."""
import json
import pathlib

import jsonschema
import pytest
from click.testing import CliRunner
from referencing import Registry, Resource

from json_cases import CASES, make_inputs
from meshmark.cli import main

SCHEMAS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "schemas"


def _registry() -> Registry:
    docs = [json.loads(p.read_text()) for p in sorted(SCHEMAS.glob("*.json"))]
    return Registry().with_resources((d["$id"], Resource.from_contents(d)) for d in docs)


REGISTRY = _registry()


def validator(name: str):
    schema = json.loads((SCHEMAS / f"{name}.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema, registry=REGISTRY)


def _strict(text: str):
    def refuse(c):
        raise AssertionError(f"non-JSON constant {c}")
    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """Every case run once, in order: (schema, args, expected status, status, stdout object, stderr)."""
    d = tmp_path_factory.mktemp("json")
    make_inputs(d)
    runs = []
    for name, args, rc in CASES:
        r = CliRunner().invoke(main, [a.format(d=d) for a in args] + ["--json"])
        runs.append((name, args, rc, r.exit_code, r.stdout, r.stderr))
    return runs


def test_every_command_is_covered_on_success_and_failure():
    """Each schema has a case that succeeds (exit 0/1) and one that fails (exit 2), and every
    command of the CLI that takes --json has a schema."""
    def leaves(cmd, prefix=()):
        import click
        if isinstance(cmd, click.Group):
            for n, c in cmd.commands.items():
                yield from leaves(c, prefix + (n,))
        elif any(getattr(p, "name", None) == "as_json" for p in cmd.params):
            yield "-".join(prefix)
    commands = set(leaves(main))
    ok = {n for n, _, rc in CASES if rc in (0, 1)}
    bad = {n for n, _, rc in CASES if rc == 2}
    assert commands == ok == bad == {p.stem for p in SCHEMAS.glob("*.json")} - {"error", "common"}


@pytest.mark.parametrize("i", range(len(CASES)), ids=[f"{n}-{rc}-{i}" for i, (n, _, rc) in enumerate(CASES)])
def test_output_validates(outputs, i):
    name, args, want, rc, out, err = outputs[i]
    assert rc == want, (args, rc, out, err)
    d = _strict(out)  # stdout is exactly one JSON document
    errors = sorted(validator(name).iter_errors(d), key=str)
    assert not errors, [f"{list(e.absolute_path)}: {e.message}" for e in errors][:5]
    if want == 2:
        assert d["ok"] is False and d["error"]["code"] == 2 and d["error"]["kind"] in ("usage", "input")
        assert d["error"]["message"] and d["error"]["message"] in err  # the same line on stderr
    else:
        assert d["ok"] is True and "error" not in d and "meshmark: " not in err
        if "detected" in d:
            assert d["detected"] is (want == 0)
        for old, new in d.get("deprecated", {}).items():  # the old names kept for one release
            assert d[old] == d[new]


def test_internal_error_is_a_json_failure(monkeypatch):
    """A bug (any exception but MeshError) under --json: exit 3 and the failure object on stdout."""
    import meshmark

    def boom(*a, **k):
        raise RuntimeError("boom")
    monkeypatch.setattr(meshmark, "mesh_info", boom)
    r = CliRunner().invoke(main, ["info", "--json"])
    d = _strict(r.stdout)
    assert r.exit_code == 3 and d == {"ok": False, "error": {"code": 3, "kind": "internal", "message": d["error"]["message"]}}
    assert d["error"]["message"].startswith("RuntimeError: boom")
    assert not list(validator("info").iter_errors(d))
    r = CliRunner().invoke(main, ["info"])  # without --json: stdout stays empty
    assert r.exit_code == 3 and r.stdout == "" and "internal error: RuntimeError: boom" in r.stderr


def test_vocabulary():
    """The vocabulary's names, never the old ones, in every schema's required keys."""
    old = {"path", "a", "b", "in", "out", "bits", "found", "marked", "tolerance", "tolerances", "set"}
    for p in SCHEMAS.glob("*.json"):
        s = json.loads(p.read_text())
        if "$defs" in s and "result" in s["$defs"]:
            r = s["$defs"]["result"]
            assert "ok" in r["required"] and not old & set(r["required"]), p.name
            for k in old & set(r["properties"]):
                assert r["properties"][k].get("deprecated") is True, (p.name, k)


def test_json_as_an_option_value_is_not_the_flag(tmp_path):
    """``--message --json`` hides the text "--json": a failure then is plain text on stderr only, and
    a bad value after a real --json still gets the failure object (the flag is processed first)."""
    make_inputs(tmp_path)
    r = CliRunner().invoke(main, ["stego", "embed", str(tmp_path / "in.obj"), str(tmp_path / "x.stl"),
                                  "--message", "--json", "--key", "s"])
    assert r.exit_code == 2 and r.stdout == "" and r.stderr.startswith("meshmark: error: STL cannot carry")
    r = CliRunner().invoke(main, ["steganalysis", "cho", str(tmp_path / "in.obj"), "--json", "--k-max", "abc"])
    d = _strict(r.stdout)
    assert r.exit_code == 2 and d["error"]["kind"] == "usage" and "'--k-max'" in d["error"]["message"]
