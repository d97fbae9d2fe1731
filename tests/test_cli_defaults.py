"""The command line and the Python API agree on defaults: what `meshmark capacity` reports is what
`meshmark.watermark.capacity` returns, for every method and both parameter sets."""
import json
import pathlib
import subprocess
import sys

import pytest

import meshmark
from meshmark.watermark import METHODS

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from conftest import shared_mesh  # noqa: E402


def _cli_capacity(path, *extra):
    r = subprocess.run([sys.executable, "-m", "meshmark.cli", "capacity", str(path), "--json", *extra],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_capacity_cli_equals_api(method):
    path = shared_mesh("classic/fandisk.obj")
    mesh = meshmark.read_mesh(path)
    default = _cli_capacity(path, "--method", method)
    thesis = _cli_capacity(path, "--method", method, "--params", "thesis")
    api_auto = meshmark.watermark.capacity(mesh, method=method)
    api_thesis = meshmark.watermark.capacity(mesh, method=method, params="thesis")
    assert default["params_mode"] == "auto" and default["capacity"] == api_auto
    assert thesis["capacity"] == api_thesis == default["thesis"]["capacity"]
    assert default["max_message_bits"] == default["auto"]["max_message_bits"]
    assert thesis["max_message_bits"] == thesis["thesis"]["max_message_bits"]


def test_bunny_laplacian_capacity_matches_table_7_1_with_thesis_parameters():
    """Table 7.1: the Bunny offers 73 carrier bits with the thesis' parameters and carrier; the default
    (local) carrier offers more."""
    path = shared_mesh("classic/bunny.obj")
    d = _cli_capacity(path, "--method", "laplacian")
    assert d["thesis"]["capacity"] == 73 and d["thesis"]["params"]["carrier"] == "thesis"
    assert d["capacity"] == meshmark.watermark.capacity(meshmark.read_mesh(path)) == 104
