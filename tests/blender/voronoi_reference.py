"""Reference values of Blender's Voronoi Texture node, evaluated by Blender itself (as
tests/blender/noise_reference.py, through geometry nodes):

    python tests/blender/voronoi_reference.py > tests/blender/voronoi_texture.json
"""
import json
import random

import bpy

import gn

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

obj = gn.point_object(points)

OUTPUTS = [("Distance", "FLOAT"), ("Color", "FLOAT_VECTOR"), ("Position", "FLOAT_VECTOR"),
           ("W", "FLOAT"), ("Radius", "FLOAT")]

out = {"blender": bpy.app.version_string, "points": [list(p) for p in points], "cases": []}
for case in CASES:
    dims, feature, metric, normalize, w, scale, detail, rough, lac, smooth, expo, rand = case

    def make(tree, pos):
        n = tree.nodes.new("ShaderNodeTexVoronoi")
        n.voronoi_dimensions = dims
        n.feature = feature
        n.distance = metric
        n.normalize = normalize
        sock = gn.link_coordinates(tree, pos, n, dims)
        if dims != "1D":
            sock["W"].default_value = w
        for name, v in (("Scale", scale), ("Detail", detail), ("Roughness", rough),
                        ("Lacunarity", lac), ("Smoothness", smooth), ("Exponent", expo),
                        ("Randomness", rand)):
            sock[name].default_value = v
        return n

    r = gn.evaluate(obj, make, OUTPUTS)
    out["cases"].append({
        "dimensions": dims, "feature": feature, "metric": metric, "normalize": normalize,
        "w": w, "scale": scale, "detail": detail, "roughness": rough, "lacunarity": lac,
        "smoothness": smooth, "exponent": expo, "randomness": rand,
        "distance": r["Distance"], "color": r["Color"], "position": r["Position"],
        "w_out": r["W"], "radius": r["Radius"],
    })
print(json.dumps(out))
