"""Reference values of Blender's Noise Texture node, evaluated by Blender itself.

Run with Blender's Python module (pip install bpy==4.2.0, Python 3.11):
    python tests/blender/noise_reference.py > tests/blender/noise_texture.json

A geometry-nodes tree evaluates Noise Texture (the node Cycles and EEVEE share with
geometry nodes, blenlib's noise) at the vertices of a point mesh: seeded random points and
round ones, for each case below, and writes the Fac and Color outputs. tests/blender_textures.rs
holds matgraph's noise_texture node to these values.
"""
import json
import random

import bpy

CASES = [
    # dimensions, type, normalize, w (1D: the point's x), scale, detail, roughness, lacunarity, offset, gain, distortion
    ("3D", "FBM", True, 0.0, 5.0, 2.0, 0.5, 2.0, 0.0, 1.0, 0.0),
    ("3D", "FBM", True, 0.0, 2.5, 0.0, 0.5, 2.0, 0.0, 1.0, 0.0),
    ("3D", "FBM", False, 0.0, 1.7, 6.5, 0.62, 2.3, 0.0, 1.0, 0.0),
    ("3D", "FBM", True, 0.0, 3.0, 8.0, 0.5, 2.0, 0.0, 1.0, 1.3),
    ("3D", "MULTIFRACTAL", True, 0.0, 2.0, 3.5, 0.6, 2.1, 0.0, 1.0, 0.0),
    ("3D", "RIDGED_MULTIFRACTAL", True, 0.0, 2.0, 4.0, 0.5, 2.0, 1.0, 2.0, 0.0),
    ("3D", "HYBRID_MULTIFRACTAL", True, 0.0, 2.0, 4.3, 0.5, 2.0, 0.5, 1.5, 0.0),
    ("3D", "HETERO_TERRAIN", True, 0.0, 2.0, 3.7, 0.5, 2.0, 0.8, 1.0, 0.0),
    ("1D", "FBM", True, 1.37, 3.0, 2.5, 0.5, 2.0, 0.0, 1.0, 0.4),
    ("2D", "FBM", True, 0.0, 4.0, 3.0, 0.55, 1.9, 0.0, 1.0, 0.7),
    ("4D", "FBM", True, -0.83, 2.2, 2.0, 0.5, 2.0, 0.0, 1.0, 0.5),
    ("4D", "RIDGED_MULTIFRACTAL", True, 2.6, 1.5, 3.0, 0.45, 2.2, 1.0, 2.0, 0.0),
]

rng = random.Random(20261205)
points = [(0.0, 0.0, 0.0), (0.5, 0.25, -0.75), (1.0, 2.0, 3.0), (-1.5, 0.1, 2.2), (123.25, -77.5, 9.0)]
points += [tuple(rng.uniform(-3.0, 3.0) for _ in range(3)) for _ in range(59)]

mesh = bpy.data.meshes.new("pts")
mesh.from_pydata(points, [], [])
obj = bpy.data.objects.new("pts", mesh)
bpy.context.scene.collection.objects.link(obj)

out = {"blender": bpy.app.version_string, "points": [list(p) for p in points], "cases": []}
for case in CASES:
    dims, ntype, normalize, w, scale, detail, rough, lac, offset, gain, dist = case
    tree = bpy.data.node_groups.new("noise", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gin = tree.nodes.new("NodeGroupInput")
    gout = tree.nodes.new("NodeGroupOutput")
    pos = tree.nodes.new("GeometryNodeInputPosition")
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.noise_dimensions = dims
    noise.noise_type = ntype
    noise.normalize = normalize
    socket = {s.name: s for s in noise.inputs}
    if dims == "1D":
        # 1D noise reads W alone: W is the point's x (the case's w is unused).
        sep = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(pos.outputs[0], sep.inputs[0])
        tree.links.new(sep.outputs[0], socket["W"])
    else:
        tree.links.new(pos.outputs[0], socket["Vector"])
    for name, v in (("W", w), ("Scale", scale), ("Detail", detail), ("Roughness", rough),
                    ("Lacunarity", lac), ("Offset", offset), ("Gain", gain), ("Distortion", dist)):
        socket[name].default_value = v
    store_f = tree.nodes.new("GeometryNodeStoreNamedAttribute")
    store_f.data_type = "FLOAT"
    store_f.inputs["Name"].default_value = "fac"
    store_c = tree.nodes.new("GeometryNodeStoreNamedAttribute")
    store_c.data_type = "FLOAT_VECTOR"
    store_c.inputs["Name"].default_value = "col"
    tree.links.new(gin.outputs[0], store_f.inputs["Geometry"])
    tree.links.new(noise.outputs["Fac"], store_f.inputs["Value"])
    tree.links.new(store_f.outputs[0], store_c.inputs["Geometry"])
    tree.links.new(noise.outputs["Color"], store_c.inputs["Value"])
    tree.links.new(store_c.outputs[0], gout.inputs[0])
    for m in list(obj.modifiers):
        obj.modifiers.remove(m)
    mod = obj.modifiers.new("gn", "NODES")
    mod.node_group = tree
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    ev = obj.evaluated_get(dg).data
    fac = [a.value for a in ev.attributes["fac"].data]
    col = [list(a.vector) for a in ev.attributes["col"].data]
    out["cases"].append({
        "dimensions": dims, "type": ntype, "normalize": normalize, "w": w, "scale": scale,
        "detail": detail, "roughness": rough, "lacunarity": lac, "offset": offset, "gain": gain,
        "distortion": dist, "fac": fac, "color": col,
    })
print(json.dumps(out))
