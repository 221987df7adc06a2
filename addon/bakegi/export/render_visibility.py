# SPDX-License-Identifier: GPL-3.0-or-later
"""Which objects a render has, against what the viewport shows. The export walks the
viewport's evaluated objects; Cycles renders and bakes the objects enabled for renders. An
object disabled in renders (its own camera toggle, or a collection's) but shown in the
viewport, a helper plane or a stand-in, is left out of the bake as Cycles leaves it out; an
object hidden in the viewport but rendered (a ceiling hidden to look into a room) is not in
the viewport's evaluation, so the bake cannot have it: the report says so, since its light
and shadow are missing."""

from .targets import some_names


def _render_hidden_collections(scene):
    """Collections disabled in renders, with every collection inside them."""
    hidden = set()

    def walk(collection, inherited):
        off = inherited or collection.hide_render
        if off:
            hidden.add(collection.name_full)
        for child in collection.children:
            walk(child, off)

    for child in scene.collection.children:
        walk(child, False)
    return hidden


class RenderVisibility:
    """Answers, for the objects of one export, whether renders have them."""

    def __init__(self, scene):
        self.hidden_collections = _render_hidden_collections(scene)
        self.left_out = []  # names of objects left out as disabled in renders
        self.instancers_left_out = []  # names of instancers renders show without themselves
        self._answers = {}  # object name -> renders (users_collection scans every collection)

    def _object_renders(self, obj):
        obj = getattr(obj, "original", obj)
        if obj is None:
            return False
        answer = self._answers.get(obj.name_full)
        if answer is None:
            collections = obj.users_collection
            # An object in several collections renders if one of them renders.
            answer = not obj.hide_render and (not collections or any(
                c.name_full not in self.hidden_collections for c in collections))
            self._answers[obj.name_full] = answer
        return answer

    def renders(self, instance):
        """Whether a depsgraph object instance is in a render: the object, and for an instance
        of a collection also the object that instances it."""
        if not self._object_renders(instance.object):
            return False
        if instance.is_instance and instance.parent is not None:
            return self._object_renders(instance.parent)
        return True

    def leave_out(self, instance):
        """Whether the bake leaves a depsgraph object instance out as renders do (disabled in
        renders, or an instancer that renders without its own mesh), noting the object."""
        original = getattr(instance.object, "original", instance.object)
        if not self.renders(instance):
            _note(self.left_out, original.name)
            return True
        if not instance.is_instance and instancer_hidden_in_renders(original):
            _note(self.instancers_left_out, original.name)
            return True
        return False


def _note(names, name):
    if name not in names:
        names.append(name)


def instancer_hidden_in_renders(obj):
    """Whether renders show an object's instances or particles but not its own geometry: an
    object with particle systems or Instancing (Vertices, Faces) hides itself in renders where
    Show Instancer > Render is off (Blender's BKE_object_visibility), whatever the viewport's
    switch, which the export's viewport evaluation follows."""
    if getattr(obj, "show_instancer_for_render", True):
        return False
    return bool(getattr(obj, "particle_systems", ())) or \
        getattr(obj, "instance_type", "NONE") in ("VERTS", "FACES")


def rendered_strands(obj):
    """Names of an object's particle systems that renders draw as strands (hair, or emitter
    particles rendered as Path): Cycles renders them as curves; the bake has meshes only."""
    names = []
    for modifier in getattr(obj, "modifiers", ()):
        if modifier.type != "PARTICLE_SYSTEM" or not modifier.show_render:
            continue
        system = modifier.particle_system
        if system.settings is not None and system.settings.render_type == "PATH":
            names.append(system.name)
    return names


def hidden_but_rendered(context, kinds):
    """Names of objects of `kinds` that renders have but the viewport hides (eye icon, or
    hidden in the viewport), whose collections are in the view layer."""
    view_layer = context.view_layer
    hidden_collections = _render_hidden_collections(context.scene)
    names = []
    for obj in context.scene.objects:
        if obj.type not in kinds or obj.hide_render:
            continue
        if obj.users_collection and all(c.name_full in hidden_collections
                                        for c in obj.users_collection):
            continue
        if view_layer.objects.get(obj.name) is None:
            continue  # its collection is excluded from the view layer: not rendered either
        if not obj.visible_get(view_layer=view_layer):
            names.append(obj.name)
    return names


def warnings_for(context, visibility, kinds):
    """The report's lines about objects the bake leaves out or cannot have."""
    lines = []
    if visibility.left_out:
        names = visibility.left_out
        lines.append(f"{len(names)} object(s) disabled in renders are left out of the bake, as "
                     f"Cycles leaves them out: {some_names(names)}")
    if visibility.instancers_left_out:
        names = visibility.instancers_left_out
        lines.append(f"{len(names)} instancer(s) that renders show without their own mesh "
                     f"(Object > Instancing > Show Instancer > Render off) are left out of the "
                     f"bake, as Cycles leaves them out; what they instance is baked: "
                     f"{some_names(names)}")
    # A render's own evaluation (the preview engine: no view layer in its context) has them.
    hidden = hidden_but_rendered(context, kinds) if getattr(context, "view_layer", None) else []
    if hidden:
        lines.append(f"{len(hidden)} object(s) hidden in the viewport but rendered are not in "
                     f"the bake (Cycles would have their light and shadow): "
                     f"{some_names(hidden)}; show them while baking")
    return lines


def modifiers_differ_in_renders(obj):
    """What differs between the viewport's and the render's modifiers of `obj` (an original
    object), as words, or "" where nothing does: a modifier on in one and off in the other, or
    a Subdivision Surface or Multiresolution of other levels. The export evaluates the viewport;
    Cycles renders (and bakes) the render's settings."""
    differences = []
    for modifier in getattr(obj, "modifiers", ()):
        if modifier.show_viewport != modifier.show_render:
            where = "renders" if modifier.show_render else "the viewport"
            differences.append(f"'{modifier.name}' on only in {where}")
        elif modifier.show_viewport and modifier.type in ("SUBSURF", "MULTIRES"):
            if modifier.levels != modifier.render_levels:
                differences.append(f"'{modifier.name}' {modifier.levels} levels in the viewport, "
                                   f"{modifier.render_levels} in renders")
    return ", ".join(differences)
