"""Reference values of Blender's Voronoi Texture node, evaluated by Blender itself (as
tests/blender/noise_reference.py, through geometry nodes):

    python tests/blender/voronoi_reference.py > tests/blender/voronoi_texture.json
"""
import json
import random

import bpy

CASES = [
    # dimensions, feature, metric, normalize, w, scale, detail, roughness, lacunarity,
    # smoothness, exponent, randomness
    ("3D", "F1", "EUCLIDEAN", False, 0.0, 5.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("3D", "F2", "EUCLIDEAN", False, 0.0, 3.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("3D", "SMOOTH_F1", "EUCLIDEAN", False, 0.0, 3.0, 0.0, 0.5, 2.0, 0.7, 0.5, 0.8),
    ("3D", "DISTANCE_TO_EDGE", "EUCLIDEAN", False, 0.0, 4.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("3D", "N_SPHERE_RADIUS", "EUCLIDEAN", False, 0.0, 4.0, 0.0, 0.5, 2.0, 1.0, 0.5, 0.9),
    ("3D", "F1", "MANHATTAN", True, 0.0, 2.5, 2.5, 0.6, 2.1, 1.0, 0.5, 1.0),
    ("3D", "F1", "CHEBYCHEV", False, 0.0, 2.5, 1.0, 0.5, 2.0, 1.0, 0.5, 0.7),
    ("3D", "F2", "MINKOWSKI", True, 0.0, 2.0, 0.0, 0.5, 2.0, 1.0, 1.7, 1.0),
    ("3D", "DISTANCE_TO_EDGE", "EUCLIDEAN", True, 0.0, 2.0, 3.3, 0.55, 2.0, 1.0, 0.5, 1.0),
    ("2D", "F1", "EUCLIDEAN", False, 0.0, 4.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("2D", "SMOOTH_F1", "MANHATTAN", True, 0.0, 3.0, 1.5, 0.5, 2.0, 0.4, 0.5, 1.0),
    ("2D", "DISTANCE_TO_EDGE", "EUCLIDEAN", False, 0.0, 4.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("1D", "F1", "EUCLIDEAN", False, 0.0, 3.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("1D", "DISTANCE_TO_EDGE", "EUCLIDEAN", False, 0.0, 3.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("1D", "SMOOTH_F1", "EUCLIDEAN", False, 0.0, 3.0, 0.0, 0.5, 2.0, 0.6, 0.5, 1.0),
    ("4D", "F1", "EUCLIDEAN", False, 0.37, 2.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("4D", "F2", "CHEBYCHEV", True, -1.2, 1.5, 1.0, 0.5, 2.0, 1.0, 0.5, 1.0),
    ("4D", "N_SPHERE_RADIUS", "EUCLIDEAN", False, 0.8, 2.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0),
]

rng = random.Random(77)
points = [(0.0, 0.0, 0.0), (0.5, 0.25, -0.75), (1.0, 2.0, 3.0), (-1.5, 0.1, 2.2)]
points += [tuple(rng.uniform(-2.0, 2.0) for _ in range(3)) for _ in range(44)]

mesh = bpy.data.meshes.new("pts")
mesh.from_pydata(points, [], [])
obj = bpy.data.objects.new("pts", mesh)
bpy.context.scene.collection.objects.link(obj)

out = {"blender": bpy.app.version_string, "points": [list(p) for p in points], "cases": []}
for case in CASES:
    dims, feature, metric, normalize, w, scale, detail, rough, lac, smooth, expo, rand = case
    tree = bpy.data.node_groups.new("v", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gin = tree.nodes.new("NodeGroupInput")
    gout = tree.nodes.new("NodeGroupOutput")
    pos = tree.nodes.new("GeometryNodeInputPosition")
    n = tree.nodes.new("ShaderNodeTexVoronoi")
    n.voronoi_dimensions = dims
    n.feature = feature
    n.distance = metric
    n.normalize = normalize
    sock = {s.name: s for s in n.inputs}
    if dims == "1D":
        sep = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(pos.outputs[0], sep.inputs[0])
        tree.links.new(sep.outputs[0], sock["W"])
    else:
        tree.links.new(pos.outputs[0], sock["Vector"])
        sock["W"].default_value = w
    for name, v in (("Scale", scale), ("Detail", detail), ("Roughness", rough),
                    ("Lacunarity", lac), ("Smoothness", smooth), ("Exponent", expo),
                    ("Randomness", rand)):
        sock[name].default_value = v
    outs = {s.name: s for s in n.outputs}
    stored = []
    geo = gin.outputs[0]
    for name, kind in (("Distance", "FLOAT"), ("Color", "FLOAT_VECTOR"), ("Position", "FLOAT_VECTOR"),
                       ("W", "FLOAT"), ("Radius", "FLOAT")):
        st = tree.nodes.new("GeometryNodeStoreNamedAttribute")
        st.data_type = kind
        st.inputs["Name"].default_value = "out_" + name.lower()
        tree.links.new(geo, st.inputs["Geometry"])
        tree.links.new(outs[name], st.inputs["Value"])
        geo = st.outputs[0]
    tree.links.new(geo, gout.inputs[0])
    for m in list(obj.modifiers):
        obj.modifiers.remove(m)
    obj.modifiers.new("gn", "NODES").node_group = tree
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    ev = obj.evaluated_get(dg).data
    get = lambda name, vec: [list(a.vector) if vec else a.value for a in ev.attributes["out_" + name].data]
    out["cases"].append({
        "dimensions": dims, "feature": feature, "metric": metric, "normalize": normalize,
        "w": w, "scale": scale, "detail": detail, "roughness": rough, "lacunarity": lac,
        "smoothness": smooth, "exponent": expo, "randomness": rand,
        "distance": get("distance", False), "color": get("color", True),
        "position": get("position", True), "w_out": get("w", False), "radius": get("radius", False),
    })
print(json.dumps(out))
