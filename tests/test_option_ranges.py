"""Issue 23: every numeric option is checked against its range before any work, with exit status 2
and the option named. The input mesh given is a file that does not exist: a check that ran after
reading it would name the file instead."""
import pytest
from click.testing import CliRunner

from meshmark.cli import main as cli

NO = "/nonexistent/in.obj"
OUT = "/nonexistent-dir/out.obj"

CASES = [  # (arguments, the option the message must name)
    (["steganalysis", "cho", NO, "--k-max", "100000000"], "--k-max"),
    (["steganalysis", "cho", NO, "--k-min", "0"], "--k-min"),
    (["steganalysis", "cho", NO, "--eps", "-1"], "--eps"),
    (["steganalysis", "cho", NO, "--eps", "nan"], "--eps"),
    (["steganalysis", "cho", NO, "--false-alarm", "1"], "--false-alarm"),
    (["steganalysis", "cho", NO, "--trim", "101"], "--trim"),
    (["steganalysis", "evaluate", NO, "--splits", "0"], "--splits"),
    (["steganalysis", "evaluate", NO, "--test-fraction", "1.5"], "--test-fraction"),
    (["steganalysis", "evaluate", NO, "--test-fraction", "nan"], "--test-fraction"),
    (["steganalysis", "train", NO, "--out", "/tmp/x.npz", "--seed", "-1"], "--seed"),
    (["attack", NO, OUT, "--type", "simplify", "--fraction", "1.5"], "--fraction"),
    (["attack", NO, OUT, "--type", "simplify", "--fraction", "0"], "--fraction"),
    (["attack", NO, OUT, "--type", "crop", "--fraction", "1"], "--fraction"),
    (["attack", NO, OUT, "--type", "noise", "--strength", "nan"], "--strength"),
    (["attack", NO, OUT, "--type", "noise", "--strength", "-0.1"], "--strength"),
    (["attack", NO, OUT, "--type", "smooth", "--lambda", "inf"], "--lambda"),
    (["attack", NO, OUT, "--type", "smooth", "--iterations", "100000000"], "--iterations"),
    (["attack", NO, OUT, "--type", "remesh", "--iterations", "0"], "--iterations"),
    (["attack", NO, OUT, "--type", "remesh", "--edge-length", "0"], "--edge-length"),
    (["attack", NO, OUT, "--type", "quantize", "--bits", "999"], "--bits"),
    (["attack", NO, OUT, "--type", "subdivide", "--levels", "50"], "--levels"),
    (["attack", NO, OUT, "--type", "scale", "--factor", "-2"], "--factor"),
    (["attack", NO, OUT, "--type", "roundtrip", "--decimals", "40"], "--decimals"),
    (["attack", NO, OUT, "--type", "noise", "--seed", "-1"], "--seed"),
    (["attack", NO, OUT, "--chain", "noise:0.001", "--seed", "-1"], "--seed"),
    (["compare", NO, NO, "--samples", "-5"], "--samples"),
    (["compare", NO, NO, "--samples", "100000000000"], "--samples"),
    (["compare", NO, NO, "--seed", "-1"], "--seed"),
    (["stego", "capacity", NO, "--tolerance", "nan"], "--tolerance"),
    (["stego", "capacity", NO, "--tolerance", "0"], "--tolerance"),
    (["stego", "capacity", NO, "--level", "99"], "--level"),
    (["stego", "extract", NO, "--key", "k", "--tolerance", "-1"], "--tolerance"),
    (["stego", "embed", NO, OUT, "--message", "m", "--key", "k", "--level", "-1"], "--level"),
    (["analyze", "degradation", NO, "--repeats", "100000000"], "--repeats"),
    (["analyze", "degradation", NO, "--seed", "-3"], "--seed"),
    (["analyze", "quantization", NO, "--tolerance", "1", "--seed", "-3"], "--seed"),
    (["analyze", "curvature", NO, "--t-min", "-3"], "--t-min"),
    (["analyze", "curvature", NO, "--t-min", "20"], "--t-min"),
    (["analyze", "curvature", NO, "--repeats", "0"], "--repeats"),
    (["embed", NO, "{tmp}/o.obj", "--message", "m", "--key", "k", "--keyfile", "{tmp}/k.json", "--K", "3"], "--K"),
    (["embed", NO, "{tmp}/o.obj", "--message", "m", "--key", "k", "--keyfile", "{tmp}/k.json", "--n-robust", "0"],
     "--n-robust"),
    (["capacity", NO, "--eps", "nan"], "--eps"),
    (["capacity", NO, "--method", "cho-mean", "--alpha", "0.9"], "--alpha"),
    (["capacity", NO, "--method", "cho-mean", "--guard", "0.3"], "--guard"),
    (["capacity", NO, "--n-thr", "0"], "--n-thr"),
    (["study", "run", "/nonexistent.toml", "--out", "/tmp/x", "--workers", "-1"], "--workers"),
    (["study", "run", "/nonexistent.toml", "--out", "/tmp/x", "--chunk-size", "0"], "--chunk-size"),
    (["study", "run", "/nonexistent.toml", "--out", "/tmp/x", "--retries", "-1"], "--retries"),
]


@pytest.mark.parametrize("args,option", CASES, ids=[" ".join(a[:2] + a[-2:]) for a, _ in CASES])
def test_out_of_range_option_is_exit_2_naming_it(tmp_path, args, option):
    r = CliRunner().invoke(cli, [a.format(tmp=tmp_path) for a in args])
    assert r.exit_code == 2, (r.exit_code, r.output)
    first = r.output.strip().splitlines()[-1]
    assert first.startswith(f"meshmark: error: {option}: "), r.output
    assert "nonexistent" not in first  # checked before the input was looked at
    assert not list(tmp_path.iterdir())  # and nothing written


def test_train_out_in_missing_folder_is_exit_2_before_training(tmp_path):
    r = CliRunner().invoke(cli, ["steganalysis", "train", NO, "--out", "/nonexistent/x.npz"])
    assert r.exit_code == 2 and "the folder /nonexistent does not exist" in r.output, r.output
