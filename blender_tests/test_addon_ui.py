"""(6) The add-on registers, its panel draws, it unregisters cleanly and registers again.

The bpy module has no window, so the panel's ``draw`` runs against a layout that checks every call
the way Blender's UILayout would: each ``prop`` must name an RNA property of the data it is given,
each ``operator`` a registered operator. (A real GUI draw runs in tools/blender_gui_smoke.py under
Debian's Blender and Xvfb.)"""
import types

import bpy
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result


class CheckingLayout:
    def __init__(self, log):
        self.log = log

    def _child(self, *a, **k):
        return CheckingLayout(self.log)

    row = column = box = split = _child

    def prop(self, data, name, **kw):
        assert name in data.bl_rna.properties, f"{data} has no property {name!r}"
        getattr(data, name)
        self.log.append(("prop", name))

    def operator(self, idname, **kw):
        mod, op = idname.split(".")
        getattr(getattr(bpy.ops, mod), op).get_rna_type()  # raises KeyError if not registered
        self.log.append(("operator", idname))

    def label(self, text="", **kw):
        assert isinstance(text, str)
        self.log.append(("label", text))


def _draw(context):
    from meshmark_blender import panels
    log = []
    panels.MESHMARK_PT_sidebar.draw(types.SimpleNamespace(layout=CheckingLayout(log)), context)
    return log


def test_panel_draws_with_and_without_a_mesh(addon):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    log = _draw(bpy.context)
    assert ("label", "Select a mesh object") in log
    ops = [x[1] for x in log if x[0] == "operator"]
    assert ops == ["meshmark.capacity", "meshmark.embed", "meshmark.save_keyfile", "meshmark.load_keyfile",
                   "meshmark.verify", "meshmark.issue_copies", "meshmark.trace", "meshmark.deformation_study"]
    props = [x[1] for x in log if x[0] == "prop"]
    assert props[:6] == ["method", "params_mode", "K", "n_thr", "n_robust", "eps"] and "message" in props
    assert "key" in props and bpy.context.scene.meshmark.params_mode == "auto"
    assert "weld" in props and bpy.context.scene.meshmark.weld is True
    s = bpy.context.scene.meshmark
    assert (s.method, s.params.laplacian.K, s.params.laplacian.n_thr, s.params.laplacian.n_robust) == ("laplacian", 0, 46, 5)
    assert abs(s.params.laplacian.eps - 1e-5) < 1e-12 and s.evaluated
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    log = _draw(bpy.context)
    assert ("label", "Message up to 31 bytes (automatic parameters)") in log  # the 31-byte cap; thesis: 1 byte
    s.params_mode = "thesis"
    assert ("label", "Capacity: 44 bits, message up to 1 bytes") in _draw(bpy.context)
    s.params_mode = "auto"
    bpy.ops.mesh.primitive_cube_add()
    assert any(x[0] == "label" and "too small" in x[1] for x in _draw(bpy.context))  # said, not raised


def test_result_is_drawn(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    bpy.ops.meshmark.embed(message="E", key="k", keyfile=str(tmp_path / "k.json"))
    bpy.ops.meshmark.verify()  # the keyfile comes from the settings Embed filled in
    log = _draw(bpy.context)
    assert ("label", "Detected  NC 1.000  CDR 1.000") in log and ("label", "Message: E") in log


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
