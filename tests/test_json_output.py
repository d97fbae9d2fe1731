"""Issue 23: JSON output never contains Infinity or NaN (meshmark.jsonout, used by every --json)."""
import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

import meshmark
from meshmark import jsonout
from meshmark.cli import main as cli


def _strict(text: str):
    """json.loads that refuses Infinity / NaN (Python's accepts them by default)."""
    def refuse(c):
        raise AssertionError(f"non-JSON constant {c} in the output")
    return json.loads(text, parse_constant=refuse)


def test_dumps_replaces_non_finite_by_null_with_a_reason():
    d = {"a": 1.5, "bbox": [float("-inf"), 0.0, np.float64("inf")], "x": float("nan"), "n": np.int64(3),
         "nested": {"v": np.array([1.0, np.nan])}, "ok": True, "s": "inf"}
    out = _strict(jsonout.dumps(d))
    assert out["a"] == 1.5 and out["n"] == 3 and out["ok"] is True and out["s"] == "inf"
    assert out["bbox"] == [None, 0.0, None] and out["bbox_reason"] == "not finite: [0] -inf, [2] inf"
    assert out["x"] is None and out["x_reason"] == "not finite: nan"
    assert out["nested"] == {"v": [1.0, None], "v_reason": "not finite: [1] nan"}
    assert "a_reason" not in out and "n_reason" not in out
    assert _strict(jsonout.dumps(float("inf"))) == {"value": None, "value_reason": "not finite: inf"}
    many = _strict(jsonout.dumps({"v": [math.inf] * 10}))
    assert many["v_reason"].endswith("and 2 more")


@pytest.fixture
def huge(tmp_path):
    """A tetrahedron with coordinates of +-1e308: its extent and diagonal overflow to inf."""
    p = tmp_path / "huge.obj"
    p.write_text("v -1e308 -1e308 -1e308\nv 1e308 -1e308 -1e308\nv -1e308 1e308 -1e308\nv -1e308 -1e308 1e308\n"
                 "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n")
    return p


def _run(args):
    r = CliRunner().invoke(cli, args)
    assert "Traceback" not in r.output and r.exit_code in (0, 1, 2), (r.exit_code, r.output)
    return r


def test_info_json_of_a_huge_mesh(huge):
    r = _run(["info", str(huge), "--json"])
    assert r.exit_code == 0, r.output
    assert "Infinity" not in r.output and "NaN" not in r.output
    d = _strict(r.output)
    assert d["bbox_min"] == [-1e308] * 3 and d["bbox_max"] == [1e308] * 3
    reasons = {k: v for k, v in d.items() if k.endswith("_reason")}
    assert reasons and all(v.startswith("not finite") for v in reasons.values())
    for k in reasons:
        field = d[k[:-len("_reason")]]
        assert field is None or (isinstance(field, list) and None in field)


@pytest.mark.parametrize("args", [
    ["compare", "{m}", "{m}", "--json", "--samples", "200"],
    ["analyze", "quantization", "{m}", "--tolerance", "1", "--json"],
    ["analyze", "degradation", "{m}", "--tolerance", "1", "--json"],
    ["stego", "capacity", "{m}", "--json"],
])
def test_other_commands_on_a_huge_mesh(huge, args):
    """Either a clean refusal (exit 2, no JSON) or strict JSON: never Infinity or NaN."""
    r = _run([a.format(m=huge) for a in args])
    assert "Infinity" not in r.output and "NaN" not in r.output
    if r.exit_code == 0:
        _strict(r.output)
