"""Reference values of Blender's Noise Texture node, evaluated by Blender itself.

Run with Blender's Python module (pip install bpy==4.2.0, Python 3.11):
    python tests/blender/noise_reference.py > tests/blender/noise_texture.json

A geometry-nodes tree evaluates Noise Texture (the node Cycles and EEVEE share with
geometry nodes, blenlib's noise) at the vertices of a point mesh: seeded random points and
round ones, for each case below, and writes the Fac and Color outputs. tests/models/blender_textures.rs
holds matgraph's noise_texture node to these values.
"""
import json
import random

import bpy

import gn

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

obj = gn.point_object(points)

out = {"blender": bpy.app.version_string, "points": [list(p) for p in points], "cases": []}
for case in CASES:
    dims, ntype, normalize, w, scale, detail, rough, lac, offset, gain, dist = case

    def make(tree, pos):
        noise = tree.nodes.new("ShaderNodeTexNoise")
        noise.noise_dimensions = dims
        noise.noise_type = ntype
        noise.normalize = normalize
        # 1D noise reads W alone: W is the point's x (the case's w is unused).
        socket = gn.link_coordinates(tree, pos, noise, dims)
        for name, v in (("W", w), ("Scale", scale), ("Detail", detail), ("Roughness", rough),
                        ("Lacunarity", lac), ("Offset", offset), ("Gain", gain),
                        ("Distortion", dist)):
            socket[name].default_value = v
        return noise

    r = gn.evaluate(obj, make, [("Fac", "FLOAT"), ("Color", "FLOAT_VECTOR")])
    out["cases"].append({
        "dimensions": dims, "type": ntype, "normalize": normalize, "w": w, "scale": scale,
        "detail": detail, "roughness": rough, "lacunarity": lac, "offset": offset, "gain": gain,
        "distortion": dist, "fac": r["Fac"], "color": r["Color"],
    })
print(json.dumps(out))
