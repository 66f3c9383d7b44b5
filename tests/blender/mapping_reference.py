"""Reference rotations for the `mapping` node: Blender's Vector Rotate in its Euler XYZ mode,
which turns a vector by the same `euler_to_mat3` matrix as the Mapping node (Mapping itself
is a shader node, which geometry nodes cannot evaluate), forwards (Mapping's point and vector
types at unit scale and zero location) and inverted (its texture type), evaluated by Blender:

    python tests/blender/mapping_reference.py > tests/blender/mapping.json
"""
import json
import math
import random

import bpy

import gn

rng = random.Random(2718)
points = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.5, -0.25, 2.0)]
points += [tuple(rng.uniform(-2.0, 2.0) for _ in range(3)) for _ in range(28)]
h = math.pi / 2
rotations = [(h, 0.0, 0.0), (0.0, h, 0.0), (0.0, 0.0, h), (h, h, 0.0), (0.3, -1.2, 2.5)]
rotations += [tuple(rng.uniform(-math.pi, math.pi) for _ in range(3)) for _ in range(7)]

obj = gn.point_object(points)
out = {"blender": bpy.app.version_string, "points": [list(p) for p in points], "rotations": []}
for rotation in rotations:
    entry = {"rotation": list(rotation)}
    for invert in [False, True]:
        def make(tree, pos, rotation=rotation, invert=invert):
            n = tree.nodes.new("ShaderNodeVectorRotate")
            n.rotation_type = "EULER_XYZ"
            n.invert = invert
            tree.links.new(pos.outputs[0], n.inputs["Vector"])
            n.inputs["Rotation"].default_value = rotation
            return n
        r = gn.evaluate(obj, make, [("Vector", "FLOAT_VECTOR")])
        entry["inverse" if invert else "forward"] = r["Vector"]
    out["rotations"].append(entry)
print(json.dumps(out))
