"""Reference values of Blender's White Noise and Gradient Texture nodes, evaluated by
Blender itself (as tests/blender/noise_reference.py, through geometry nodes):

    python tests/blender/textures_reference.py > tests/blender/textures.json
"""
import json
import random

import bpy

import gn

rng = random.Random(4242)
points = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.5), (0.25, 0.25, 0.25)]
points += [tuple(rng.uniform(-1.5, 1.5) for _ in range(3)) for _ in range(43)]

obj = gn.point_object(points)


def evaluate(make, value):
    """position → the node `make` makes → its `value` output and colour."""
    r = gn.evaluate(obj, make, [(value, "FLOAT"), ("Color", "FLOAT_VECTOR")])
    return r[value], r["Color"]


out = {"blender": bpy.app.version_string, "points": [list(p) for p in points],
       "white_noise": [], "gradient": []}
for dims in ["1D", "2D", "3D", "4D"]:
    def make(tree, pos, dims=dims):
        n = tree.nodes.new("ShaderNodeTexWhiteNoise")
        n.noise_dimensions = dims
        sock = gn.link_coordinates(tree, pos, n, dims)
        if dims != "1D":
            sock["W"].default_value = 0.625
        return n
    fac, col = evaluate(make, "Value")
    out["white_noise"].append({"dimensions": dims, "w": 0.625, "value": fac, "color": col})
for kind in ["LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL"]:
    def make(tree, pos, kind=kind):
        n = tree.nodes.new("ShaderNodeTexGradient")
        n.gradient_type = kind
        tree.links.new(pos.outputs[0], n.inputs["Vector"])
        return n
    fac, col = evaluate(make, "Fac")
    out["gradient"].append({"type": kind, "fac": fac, "color": col})
print(json.dumps(out))
