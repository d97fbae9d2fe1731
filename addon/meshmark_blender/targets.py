"""The objects one mark covers: one mesh object, or the parts of a character taken as one carrier.

A character usually comes as several objects skinned to one armature (the Knight: body, head, two
arms, two legs). Marked one by one, each part is too small to carry much; read one by one, each holds
a fraction of the evidence. A :class:`Target` joins its objects' meshes side by side
(:func:`meshmark.parts.join`: no vertex merged, nothing changed in Blender), so Embed, Verify, Issue
and Trace mark and read all of them as one carrier with one keyfile, and the marked positions are
split back into the objects.

Order: the objects are taken sorted by name, and the keyfile records them (``mesh.parts``: object
name, vertex and face count, in carrier order), so Verify rebuilds the same join from any one of the
parts and says which part is missing or changed (:func:`for_keyfile`).
"""
from __future__ import annotations

import bpy

from meshmark import parts as _parts

from . import bridge, words
from .bridge import BlenderInputError


class Target:
    """Mesh objects marked and read as one carrier (in this order)."""

    def __init__(self, objects):
        self.objects = list(objects)
        if not self.objects:
            raise BlenderInputError("no mesh object: select a mesh object first")
        for o in self.objects:
            if o.type != "MESH":
                raise BlenderInputError(f"'{o.name}' is a {o.type.lower()}, not a mesh")
            if o.mode == "EDIT":
                raise BlenderInputError(f"'{o.name}' is in Edit Mode: switch to Object Mode first")

    @property
    def names(self) -> list:
        return [o.name for o in self.objects]

    @property
    def label(self) -> str:
        """``'Suzanne'`` or ``'Knight_ArmLeft and 5 more'``."""
        return self.objects[0].name if len(self.objects) == 1 else f"{self.objects[0].name} and {len(self.objects) - 1} more"

    @property
    def quoted(self) -> str:
        return f"'{self.objects[0].name}'" if len(self.objects) == 1 else f"the {len(self.objects)} objects {words.names(self.names)}"

    def base(self) -> _parts.Joined:
        """The objects' base meshes (their Basis) joined."""
        return _parts.join([bridge.base_mesh(o) for o in self.objects])

    def evaluated(self, context) -> _parts.Joined:
        """The objects as evaluated now, joined (call within :func:`bridge.cage_only`)."""
        return _parts.join([bridge.evaluated_mesh(context, o) for o in self.objects])

    def record(self, joined: _parts.Joined) -> list:
        """What the keyfile keeps about the parts (``mesh.parts``)."""
        nv, nf = joined.offsets, joined.face_offsets
        return [{"object": o.name, "n_vertices": int(nv[i + 1] - nv[i]), "n_faces": int(nf[i + 1] - nf[i])}
                for i, o in enumerate(self.objects)]

    def signature(self) -> tuple:
        """Changes when an object's mesh is replaced or its vertex/face count changes (panel caches)."""
        return tuple((o.name, o.data.name, len(o.data.vertices), len(o.data.polygons)) for o in self.objects)


def from_selection(context, objects=None) -> Target:
    """The target of an operator: ``objects`` (names or objects) if given, else the selected mesh
    objects with the active one (other selected kinds, such as the armature, are left out)."""
    if objects is not None:
        objs = []
        for o in ([objects] if isinstance(objects, (str, bpy.types.Object)) else objects):
            ob = bpy.data.objects.get(o) if isinstance(o, str) else o
            if ob is None:
                raise BlenderInputError(f"there is no object named '{o}'")
            objs.append(ob)
        return Target(sorted(dict.fromkeys(objs), key=lambda ob: ob.name))
    active = bridge.active_mesh_object(context)
    chosen = {o for o in getattr(context, "selected_objects", ()) if o.type == "MESH"} | {active}
    return Target(sorted(chosen, key=lambda ob: ob.name))


def armatures_of(obj) -> list:
    return [m.object for m in getattr(obj, "modifiers", ()) if m.type == "ARMATURE" and m.object is not None]


def character_parts(context, obj) -> list:
    """Every mesh object of the scene skinned to an armature that ``obj`` is skinned to (``obj``
    included), sorted by name; ``[obj]`` when it is not skinned."""
    rigs = set(armatures_of(obj))
    if not rigs:
        return [obj]
    found = [o for o in context.scene.objects if o.type == "MESH" and rigs & set(armatures_of(o))]
    return sorted(set(found) | {obj}, key=lambda o: o.name)


def left_out(context, target: Target) -> list:
    """Parts of the target's character(s) that are not in the target (their names)."""
    have = set(target.names)
    out = []
    for o in target.objects:
        out += [p.name for p in character_parts(context, o) if p.name not in have and p.name not in out]
    return out


def recorded_parts(kf) -> list:
    """The keyfile's parts (``[{"object", "n_vertices", "n_faces"}]``; [] for a keyfile without them)."""
    parts = kf.mesh.get("parts") if isinstance(kf.mesh, dict) else None
    ok = isinstance(parts, list) and all(isinstance(p, dict) and isinstance(p.get("object"), str) for p in parts)
    return parts if ok else []


def for_keyfile(context, kf, chosen: Target):
    """(target to read, notes) for verifying ``chosen`` with keyfile ``kf``.

    If the keyfile covers several objects and one of them is chosen, the target is the keyfile's
    parts in its order (the character as marked), whatever else is selected; a part that is not in
    the scene is left out and named, a part whose vertex count changed is named. Otherwise the
    chosen objects are read as they are (a posed export imported under another name, say)."""
    parts = recorded_parts(kf)
    names = [p["object"] for p in parts]
    if len(names) <= 1 or not set(chosen.names) & set(names):
        return chosen, {"missing": [], "changed": []}
    objs, missing, changed = [], [], []
    scene_objects = context.scene.objects
    for p in parts:
        o = scene_objects.get(p["object"])
        if o is None or o.type != "MESH":
            missing.append(p["object"])
            continue
        if isinstance(p.get("n_vertices"), int) and len(o.data.vertices) != p["n_vertices"]:
            changed.append(f"{o.name} ({len(o.data.vertices)} vertices, {p['n_vertices']} when marked)")
        objs.append(o)
    return Target(objs), {"missing": missing, "changed": changed}
