"""(6) The add-on registers, its panels draw, it unregisters cleanly and registers again.

The bpy module has no window, so the panels' ``draw`` runs against a recording layout
(blender_tests/ui_layout.py) that checks every call the way Blender's UILayout would (each ``prop``
must name an RNA property of the data it is given, each ``operator`` a registered operator) and
measures every text with ``blf.dimensions`` against the slot it gets at the default sidebar width.
The same layout records the real draw in Debian's Blender 3.4 under Xvfb (test_blender_ui.py)."""
import json

import bpy
import pytest

import meshmark
from blender_tests import rigs, ui_layout
from blender_tests.rigs import last_result


def _draw(context, width=None):
    """{panel label: [(kind, text, need, slot)]} over the registered Meshmark panels."""
    from meshmark_blender import panels
    width = width or (panels.DEFAULT_REGION_WIDTH - ui_layout.SIDEBAR_MARGIN) * ui_layout.scale()
    out = {}
    for cls in panels._registered:
        items = ui_layout.measure(ui_layout.draw_recorded(cls, context), width)
        out[cls.bl_label] = items
    return out


def _texts(drawn, kind=None):
    return [i.text for items in drawn.values() for i in items if kind is None or i.kind == kind]


def _ops(drawn):
    return [i.detail for items in drawn.values() for i in items if i.kind == "operator"]


def _no_truncation(drawn):
    bad = {k: ui_layout.truncated(v) for k, v in drawn.items() if ui_layout.truncated(v)}
    assert not bad, f"texts wider than their place at the default sidebar width: {bad}"


def test_panels_draw_with_and_without_a_mesh(addon):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    from meshmark_blender import panels
    # Watermark, Trace copies (meshmark.issue_copies / meshmark.trace are registered), Steganography,
    # Analysis, Steganalysis and Study
    assert [c.bl_label for c in panels._registered] == ["Meshmark", "Watermark", "Trace copies", "Steganography",
                                                        "Analysis", "Steganalysis", "Study"]
    assert panels.MESHMARK_PT_trace.needs == ("meshmark.issue_copies", "meshmark.trace")
    assert all(c.bl_parent_id == "MESHMARK_PT_sidebar" for c in panels.SUBPANELS)
    d = _draw(bpy.context)
    assert "Select a mesh object" in _texts({"m": d["Meshmark"]})
    assert _ops(d) == ["meshmark.load_keyfile", "meshmark.save_keyfile", "meshmark.capacity", "meshmark.embed",
                       "meshmark.verify", "meshmark.issue_copies", "meshmark.trace", "meshmark.stego_embed",
                       "meshmark.stego_extract", "meshmark.analyze", "meshmark.steganalysis_detect",
                       "meshmark.deformation_study", "meshmark.study"]
    props = [i.detail for items in d.values() for i in items if i.kind == "prop"]
    assert props.count("keyfile") == 1  # one keyfile field
    assert {"method", "message", "key", "evaluated", "show_advanced", "frames_auto", "output_dir"} <= set(props)
    assert "K" not in props and "weld" not in props  # under the Advanced fold, closed by default
    s = bpy.context.scene.meshmark
    assert (s.method, s.param_mode, s.params.laplacian.K, s.params.laplacian.n_thr) == ("laplacian", "AUTO", 0, 46)
    assert abs(s.params.laplacian.eps - 1e-5) < 1e-12 and s.evaluated and s.weld
    _no_truncation(d)
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    d = _draw(bpy.context)
    # Settings: Auto (the default) shows the longest text the automatic choice takes (the 31-byte cap
    # here); Custom shows the fields' capacity (the published numbers with the carrier field, "local": 77 carriers, 3 bytes with the keyed check)
    assert ["Automatic settings", "Fits 31 bytes of text"] == [t for t in _texts(d, "label") if "utomatic" in t or "Fits" in t]
    _no_truncation(d)
    # Custom starts from what Auto would use for the message ("meshmark": 64 bits need 126 carriers; the
    # third rung, N/35 bins, is the first with as many: 156), so switching changes nothing until a field
    # is edited
    s.param_mode = "CUSTOM"
    assert (s.params.laplacian.K, s.params.laplacian.n_thr, s.params.laplacian.n_robust) == (572, 23, 2)
    d = _draw(bpy.context)
    assert ["Capacity 156 bits", "Fits 10 bytes of text"] == [t for t in _texts(d, "label") if "apacity" in t or "Fits" in t]
    s.params.laplacian.K, s.params.laplacian.n_thr, s.params.laplacian.n_robust = 0, 46, 5  # the thesis numbers
    d = _draw(bpy.context)
    assert ["Capacity 77 bits", "Fits 3 bytes of text"] == [t for t in _texts(d, "label") if "apacity" in t or "Fits" in t]
    s.param_mode = "AUTO"
    bpy.ops.mesh.primitive_cube_add()
    assert "Mesh too small to" in _texts(_draw(bpy.context), "label")  # said (wrapped), not raised


def test_advanced_fold_shows_only_the_chosen_methods_settings(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    s = bpy.context.scene.meshmark
    s.show_advanced = True
    d = _draw(bpy.context)
    labels = _texts(d, "label")
    i = labels.index("Embed will use:")  # Auto: what Embed will use for the message
    assert labels[i + 1:i + 4] == ["Bins 572", "Min. pair size 23", "Lightness 2"]
    from meshmark_blender import targets
    from meshmark_blender.tasks.watermark import plan
    want = plan(targets.Target([bpy.context.active_object]), "laplacian", s.message)["params"]
    assert (want["K"], want["n_thr"], want["n_robust"]) == (572, 23, 2)  # the choice Embed makes
    assert bpy.ops.meshmark.embed(key="k", keyfile=str(tmp_path / "k.json")) == {"FINISHED"}
    assert {k: last_result()["params"][k] for k in ("K", "n_thr", "n_robust")} == {"K": 572, "n_thr": 23, "n_robust": 2}
    assert [i.text for i in d["Watermark"] if i.detail == "param_mode"] == ["Auto", "Custom"]
    _no_truncation(d)
    s.param_mode = "CUSTOM"
    expected = {"laplacian": ["K", "n_thr", "n_robust", "thesis_exact", "solver"],  # eps: not for artists
                "radial": ["K", "n_thr", "origin_mode", "origin_iters"],
                "cho-mean": ["K", "alpha", "delta_k", "guard", "center_iters", "thesis_exact"],
                "cho-variance": ["K", "alpha", "delta_k", "guard", "center_iters", "thesis_exact"]}
    for method, names in expected.items():
        s.method = method
        d = _draw(bpy.context)
        shown = [i.detail for i in d["Watermark"] if i.kind == "prop" and i.detail in
                 {n for v in expected.values() for n in v}]
        assert shown == names, method
        assert "weld" in [i.detail for i in d["Watermark"]]
        _no_truncation(d)
    # every choice is a menu, with the method's default first
    rna = s.params.laplacian.bl_rna.properties
    assert rna["solver"].type == "ENUM" and [e.identifier for e in rna["solver"].enum_items] == ["iterative", "direct"]
    rna = s.params.radial.bl_rna.properties
    assert rna["origin_mode"].type == "ENUM" and s.params.radial.origin_mode == "axis"
    assert rna["n_thr"].name == "Strength" and abs(getattr(s.params, "cho-variance").alpha - 0.16) < 1e-7
    assert [e.identifier for e in s.bl_rna.properties["param_mode"].enum_items] == ["AUTO", "CUSTOM"]
    assert s.bl_rna.properties["method"].type == "ENUM"


def test_tooltips_speak_to_artists(addon):
    from meshmark_blender import params
    for name in params.METHODS:
        for p in params.method_params(name):
            assert "eq." not in p.description and "§" not in p.description and "thesis" not in p.description, p.name
            assert len(p.label) <= 16, p.label
    for rna in (bpy.context.scene.meshmark.bl_rna, bpy.ops.meshmark.embed.get_rna_type()):
        for prop in rna.properties:
            assert "eq." not in prop.description and "§" not in prop.description, prop.identifier


def test_result_is_drawn_for_its_object_only(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ele = rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    bpy.ops.meshmark.embed(message="E", key="k", keyfile=str(tmp_path / "k.json"))
    bpy.ops.meshmark.verify()  # the keyfile comes from the settings Embed filled in
    labels = _texts(_draw(bpy.context), "label")
    assert {"Mark found", "Bits matching 100%", "Message: E"} <= set(labels)
    assert last_result()["operator"] == "meshmark.verify" and last_result()["object"] == "elephant"
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    bpy.context.scene.collection.objects.link(cam)
    rigs.select_only(cam)
    labels = _texts(_draw(bpy.context), "label")
    assert "Mark found" not in labels and "Select a mesh object" in labels  # the elephant's result is hidden
    with pytest.raises(RuntimeError):
        bpy.ops.meshmark.capacity()
    assert "Mark found" not in _texts(_draw(bpy.context), "label")
    assert any("not a mesh" in t for t in _texts(_draw(bpy.context), "label"))  # the camera's own error
    rigs.select_only(ele)
    labels = _texts(_draw(bpy.context), "label")
    assert not any("not a mesh" in t for t in labels)  # the camera's error is not shown for the elephant


def test_embed_side_panel_repeats_no_fields(addon, tmp_path):
    """The Embed file browser (and redo panel) draws the operator: a summary, no second set of fields."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    import types
    from meshmark_blender.operators import watermark
    rec = ui_layout.RecordingLayout()
    op = types.SimpleNamespace(layout=rec, bits="", confirm=False,
                               properties=types.SimpleNamespace(is_property_set=lambda n: False),
                               arg=lambda context, n: getattr(context.scene.meshmark, n))
    watermark.MESHMARK_OT_embed.draw(op, bpy.context)
    items = ui_layout.measure(rec, 200)
    assert [i.kind for i in items] == ["label"] * 4
    assert [i.text for i in items] == ["elephant", "Laplacian", "8-byte message", "Key: missing"]


def test_keyfile_save_and_load(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    bpy.ops.meshmark.embed(message="E", key="secret", keyfile=str(tmp_path / "k.json"))
    assert bpy.ops.meshmark.save_keyfile(filepath=str(tmp_path / "copy.json")) == {"FINISHED"}
    s = bpy.context.scene.meshmark
    s.message, s.key, s.params.laplacian.n_thr, s.weld = "other", "", 10, False
    assert bpy.ops.meshmark.load_keyfile(filepath=str(tmp_path / "copy.json")) == {"FINISHED"}
    assert (s.message, s.key, s.params.laplacian.n_thr, s.params.laplacian.K) == ("E", "secret", 46, 286)
    assert s.weld is True and last_result()["weld"] is True
    assert s.keyfile == str(tmp_path / "copy.json")


def test_register_unregister_register(addon):
    addon.unregister()
    assert not hasattr(bpy.types.Scene, "meshmark")
    assert not hasattr(bpy.types, "MESHMARK_PT_sidebar")
    with pytest.raises(KeyError):
        bpy.ops.meshmark.embed.get_rna_type()
    addon.register()
    assert hasattr(bpy.types, "MESHMARK_PT_sidebar") and bpy.types.MESHMARK_PT_sidebar.bl_category == "Meshmark"
    addon.unregister()
    addon.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.context.scene.meshmark.method == "laplacian"
    assert bpy.ops.meshmark.embed.get_rna_type().properties["K"].default == 0


def test_every_result_and_capacity_text_fits(addon, tmp_path, monkeypatch):
    """The result lines of embed, verify, an error and the study, and the capacity line of a mesh
    too large to count on the fly, at the default sidebar width."""
    from meshmark_blender import panels
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    monkeypatch.setattr(panels.watermark, "AUTO_CAPACITY_MAX_VERTICES", 1000)
    d = _draw(bpy.context)
    assert "Capacity not counted" in _texts(d, "label")  # beside the refresh button
    _no_truncation(d)
    bpy.ops.meshmark.embed(message="E", key="k", keyfile=str(tmp_path / "k.json"))
    d = _draw(bpy.context)
    assert {"Marked", "77 bits in the mesh", "Capacity not counted"} <= set(_texts(d, "label"))
    _no_truncation(d)
    with pytest.raises(RuntimeError):
        bpy.ops.meshmark.embed(message="a much longer text", key="k", keyfile=str(tmp_path / "k.json"),
                               params="thesis", overwrite=True)  # consent given: it fails on the length
    d = _draw(bpy.context)
    err = last_result()["error"]
    labels = _texts(d, "label")
    first = next(i for i, t in enumerate(labels) if t.startswith("message too long"))
    box = labels[first:first + len(err)]
    assert err.startswith("message too long for this mesh") and " ".join(box).startswith(err) and len(box) > 3
    _no_truncation(d)
    bpy.ops.meshmark.deformation_study(frame_start=1, frame_end=2, output_dir=str(tmp_path))
    d = _draw(bpy.context)
    assert {"Found on 2/2 frames", "Message on 2 frames", "Bits matching 100%"} <= set(_texts(d, "label"))
    _no_truncation(d)


def test_friendly_errors():
    from meshmark_blender.messages import friendly
    assert friendly("the Laplacian lengths span an empty range (all equal?): cannot form bins").startswith(
        "mesh too small to carry a mark")
    assert friendly("the laplacian mark does not take on this mesh: 3 of 40 carrier bits still read wrong after 4 "
                    "rounds (K=286, n_thr=46); nothing was changed. Try other parameters.") == (
        "the mark does not hold on this mesh (3 of 40 bits would read back wrong with Bins 286, Min. pair size 46); "
        "nothing was changed. Try other settings under Advanced")
    assert friendly("the message is 40 bytes (320 bits); at most 31 bytes fit a frame") == \
        "message too long: 40 bytes, at most 31 bytes fit in a mark"
    assert friendly("n_robust must be >= 1, got 0", "laplacian") == "Lightness must be >= 1, got 0"
    assert friendly("alpha must be in (0, 0.5) for the cho-mean method, got 0.7") == \
        "Strength must be in (0, 0.5) for the cho-mean method, got 0.7"
    # names inside paths and words are left alone
    assert friendly("cannot read keyfile '/tmp/K=1/n_thr.json': No such file") == \
        "cannot read keyfile '/tmp/K=1/n_thr.json': No such file"
