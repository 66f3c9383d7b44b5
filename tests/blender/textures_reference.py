"""Reference values of Blender's White Noise and Gradient Texture nodes, evaluated by
Blender itself (as tests/blender/noise_reference.py, through geometry nodes):

    python tests/blender/textures_reference.py > tests/blender/textures.json
"""
import json
import random

import bpy

rng = random.Random(4242)
points = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.5), (0.25, 0.25, 0.25)]
points += [tuple(rng.uniform(-1.5, 1.5) for _ in range(3)) for _ in range(43)]

mesh = bpy.data.meshes.new("pts")
mesh.from_pydata(points, [], [])
obj = bpy.data.objects.new("pts", mesh)
bpy.context.scene.collection.objects.link(obj)


def evaluate(make):
    """Builds position → node (made by `make`) → stored attributes, returns (value, color)."""
    tree = bpy.data.node_groups.new("t", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gin = tree.nodes.new("NodeGroupInput")
    gout = tree.nodes.new("NodeGroupOutput")
    pos = tree.nodes.new("GeometryNodeInputPosition")
    value_out, color_out = make(tree, pos)
    store_f = tree.nodes.new("GeometryNodeStoreNamedAttribute")
    store_f.data_type = "FLOAT"
    store_f.inputs["Name"].default_value = "fac"
    store_c = tree.nodes.new("GeometryNodeStoreNamedAttribute")
    store_c.data_type = "FLOAT_VECTOR"
    store_c.inputs["Name"].default_value = "col"
    tree.links.new(gin.outputs[0], store_f.inputs["Geometry"])
    tree.links.new(value_out, store_f.inputs["Value"])
    tree.links.new(store_f.outputs[0], store_c.inputs["Geometry"])
    tree.links.new(color_out, store_c.inputs["Value"])
    tree.links.new(store_c.outputs[0], gout.inputs[0])
    for m in list(obj.modifiers):
        obj.modifiers.remove(m)
    obj.modifiers.new("gn", "NODES").node_group = tree
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    ev = obj.evaluated_get(dg).data
    return ([a.value for a in ev.attributes["fac"].data],
            [list(a.vector) for a in ev.attributes["col"].data])


out = {"blender": bpy.app.version_string, "points": [list(p) for p in points],
       "white_noise": [], "gradient": []}
for dims in ["1D", "2D", "3D", "4D"]:
    def make(tree, pos, dims=dims):
        n = tree.nodes.new("ShaderNodeTexWhiteNoise")
        n.noise_dimensions = dims
        sock = {s.name: s for s in n.inputs}
        if dims == "1D":
            sep = tree.nodes.new("ShaderNodeSeparateXYZ")
            tree.links.new(pos.outputs[0], sep.inputs[0])
            tree.links.new(sep.outputs[0], sock["W"])
        else:
            tree.links.new(pos.outputs[0], sock["Vector"])
            sock["W"].default_value = 0.625
        return n.outputs["Value"], n.outputs["Color"]
    fac, col = evaluate(make)
    out["white_noise"].append({"dimensions": dims, "w": 0.625, "value": fac, "color": col})
for kind in ["LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL"]:
    def make(tree, pos, kind=kind):
        n = tree.nodes.new("ShaderNodeTexGradient")
        n.gradient_type = kind
        tree.links.new(pos.outputs[0], n.inputs["Vector"])
        return n.outputs["Fac"], n.outputs["Color"]
    fac, col = evaluate(make)
    out["gradient"].append({"type": kind, "fac": fac, "color": col})
print(json.dumps(out))
