"""Every CLI command with --json, once on success and once on a failure (tests/test_json_schema.py):
(schema name, arguments, expected exit status). ``{d}`` is the module's work folder."""
import meshmark
from meshmark.shapes import default_mesh, torus

SMALL_STUDY = """[study]
name = "json"
seeds = [0]
payload_bits = 8
[meshes]
paths = ["builtin:torus"]
[[methods]]
name = "none"
[[attacks]]
name = "none"
[measurements]
list = ["rmse"]
"""

# (schema, args, exit status); run in this order (later cases use files the earlier wrote)
CASES = [
    ("info", ["info"], 0),
    ("info", ["info", "{d}/missing.obj"], 2),
    ("capacity", ["capacity", "{d}/in.obj"], 0),
    ("capacity", ["capacity", "{d}/in.obj", "--K", "1"], 2),
    ("embed", ["embed", "{d}/in.obj", "{d}/out.ply", "--message", "h", "--key", "k1", "--keyfile", "{d}/k.json"], 0),
    ("embed", ["embed", "{d}/in.obj", "{d}/out2.ply", "--key", "k1", "--keyfile", "{d}/k2.json"], 2),
    ("extract", ["extract", "{d}/out.ply", "--keyfile", "{d}/k.json"], 0),
    ("extract", ["extract", "{d}/in.obj", "--keyfile", "{d}/k.json"], 1),
    ("extract", ["extract", "{d}/out.ply", "--keyfile", "{d}/missing.json"], 2),
    ("compare", ["compare", "{d}/in.obj", "{d}/out.ply", "--samples", "100"], 0),
    ("compare", ["compare", "{d}/in.obj", "{d}/missing.ply"], 2),
    ("attack", ["attack", "{d}/in.obj", "{d}/att.ply", "--type", "noise", "--strength", "0.001"], 0),
    ("attack", ["attack", "{d}/in.obj", "{d}/att2.ply", "--type", "blur"], 2),
    ("issue", ["issue", "{d}/in.obj", "{d}/copies", "--copies", "2", "--key", "k", "--registry", "{d}/r.sqlite"], 0),
    ("issue", ["issue", "{d}/in.obj", "{d}/copies", "--key", "k", "--registry", "{d}/r.sqlite"], 2),
    ("trace", ["trace", "{d}/copies/in-0001.obj", "--registry", "{d}/r.sqlite"], 0),
    ("trace", ["trace", "{d}/torus.obj", "--registry", "{d}/r.sqlite"], 1),
    ("trace", ["trace", "{d}/in.obj", "--registry", "{d}/missing.sqlite"], 2),
    ("analyze-degradation", ["analyze", "degradation", "{d}/in.obj", "--tolerance", "1"], 0),
    ("analyze-degradation", ["analyze", "degradation", "{d}/in.obj", "--tolerance", "abc"], 2),
    ("analyze-quantization", ["analyze", "quantization", "{d}/in.obj", "--tolerance", "1"], 0),
    ("analyze-quantization", ["analyze", "quantization", "{d}/in.obj", "--tolerance", "-1"], 2),
    ("analyze-quantize", ["analyze", "quantize", "{d}/in.obj", "{d}/q.ply", "--tolerance", "1"], 0),
    ("analyze-quantize", ["analyze", "quantize", "{d}/in.obj", "{d}/q.ply"], 2),
    ("analyze-curvature", ["analyze", "curvature", "{d}/in.obj"], 0),
    ("analyze-curvature", ["analyze", "curvature", "{d}/in.obj", "--t-min", "20"], 2),
    ("stego-embed", ["stego", "embed", "{d}/in.obj", "{d}/st.ply", "--message", "hi", "--key", "s"], 0),
    ("stego-embed", ["stego", "embed", "{d}/in.obj", "{d}/st.stl", "--message", "hi", "--key", "s"], 2),
    ("stego-extract", ["stego", "extract", "{d}/st.ply", "--key", "s"], 0),
    ("stego-extract", ["stego", "extract", "{d}/st.ply", "--key", "wrong"], 1),
    ("stego-extract", ["stego", "extract", "{d}/st.ply"], 2),
    ("stego-capacity", ["stego", "capacity", "{d}/in.obj"], 0),
    ("stego-capacity", ["stego", "capacity", "{d}/in.obj", "--tolerance", "0"], 2),
    ("steganalysis-features", ["steganalysis", "features", "{d}/in.obj"], 0),
    ("steganalysis-features", ["steganalysis", "features", "{d}/in.obj", "--set", "nope"], 2),
    ("steganalysis-cho", ["steganalysis", "cho", "{d}/in.obj"], 1),
    ("steganalysis-cho", ["steganalysis", "cho", "{d}/in.obj", "--k-max", "abc"], 2),
    ("steganalysis-detect", ["steganalysis", "detect", "{d}/in.obj"], 1),
    ("steganalysis-detect", ["steganalysis", "detect", "{d}/missing.obj"], 2),
    ("steganalysis-train", ["steganalysis", "train", "{d}/covers", "--out", "{d}/model.npz", "--methods", "none",
                            "--stego", "{d}/out.ply", "--stego", "{d}/st.ply", "--classifier", "qda",
                            "--domain-rate", "0"], 0),
    ("steganalysis-train", ["steganalysis", "train", "{d}/nothing", "--out", "{d}/model2.npz"], 2),
    ("steganalysis-evaluate", ["steganalysis", "evaluate", "{d}/covers", "{d}/in.obj", "{d}/torus.obj",
                               "--no-dedup", "--methods", "cho-mean", "--splits", "1",
                               "--classifier", "qda", "--set", "nvt36s"], 0),
    ("steganalysis-evaluate", ["steganalysis", "evaluate", "{d}/covers", "--splits", "0"], 2),
    ("study-run", ["study", "run", "{d}/s.toml", "--out", "{d}/study", "--workers", "0", "--no-progress"], 0),
    ("study-run", ["study", "run", "{d}/s.toml", "--out", "{d}/study", "--workers", "-1"], 2),
    ("study-status", ["study", "status", "{d}/study"], 0),
    ("study-status", ["study", "status", "{d}/missing"], 2),
    ("study-plot", ["study", "plot", "{d}/study"], 0),
    ("study-plot", ["study", "plot", "{d}/missing"], 2),
]


def make_inputs(d) -> None:
    """The meshes and the spec the cases read: the built-in default mesh, a torus, three covers."""
    meshmark.write_mesh(d / "in.obj", default_mesh())
    meshmark.write_mesh(d / "torus.obj", torus(32, 16))
    (d / "covers").mkdir()
    for i, (a, b) in enumerate([(24, 12), (28, 14), (32, 16), (36, 18)]):
        meshmark.write_mesh(d / "covers" / f"t{i}.obj", torus(a, b, minor_radius=0.2 + 0.05 * i))
    (d / "s.toml").write_text(SMALL_STUDY)
