"""Reference values of Blender's Color Ramp, Float Curve and RGB Curves nodes, evaluated by
Blender itself through geometry nodes (tests/blender/gn.py):

    python tests/blender/ramps_reference.py > tests/blender/ramps.json

Every number is f32-exact (seeded random). Ramp stops are given to Blender sorted by position
and at distinct positions (its ColorBand expects them so); curve points sorted by x, distinct,
in [0, 1]² (Blender clips them to its clipping rectangle). Factors/values run past both ends;
curves alternate Blender's Extend Horizontal and Extend Extrapolated (its default).
"""
import json
import random
import struct

import bpy

import gn

N = 64
MODES = ["CONSTANT", "LINEAR", "EASE", "CARDINAL", "B_SPLINE"]


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


rng = random.Random(0x5A3D)


def stops(n):
    pos = sorted(f32(rng.uniform(0.0, 1.0)) for _ in range(n))
    return [(p, [f32(rng.uniform(0.0, 1.0)) for _ in range(4)]) for p in pos]


def curve(n):
    xs = sorted(set(f32(rng.uniform(0.0, 1.0)) for _ in range(n)))
    return [(x, f32(rng.uniform(0.0, 1.0))) for x in xs]


def set_points(cm, pts):
    while len(cm.points) < len(pts):
        cm.points.new(0.5, 0.5)
    for p, (x, y) in zip(cm.points, pts):
        p.location = (x, y)
        p.handle_type = "AUTO"


facs = [-0.25, 0.0, 0.25, 0.5, 1.0, 1.25] + [f32(rng.uniform(-0.2, 1.2)) for _ in range(N - 6)]
obj = gn.point_object([(x, 0.0, 0.0) for x in facs])
out = {"blender": bpy.app.version_string, "x": facs, "ramps": [], "float_curves": [],
       "rgb_curves": []}

for case in range(15):
    mode = MODES[case % 5]
    st = stops([2, 3, 5, 9, 16][case // 3])

    def make(tree, pos, st=st, mode=mode):
        n = tree.nodes.new("ShaderNodeValToRGB")
        ramp = n.color_ramp
        ramp.interpolation = mode
        ramp.color_mode = "RGB"
        els = ramp.elements
        while len(els) < len(st):
            els.new(0.5)
        for e, (p, c) in zip(els, st):
            e.position = p
            e.color = c
        # What Blender holds (it may re-sort elements as they move), in its order.
        st[:] = [(e.position, list(e.color)) for e in els]
        sep = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(pos.outputs[0], sep.inputs[0])
        tree.links.new(sep.outputs[0], n.inputs["Fac"])
        return n

    r = gn.evaluate(obj, make, [("Color", "FLOAT_VECTOR"), ("Alpha", "FLOAT")])
    out["ramps"].append({"interpolation": mode.lower(), "stops": st, "color": r["Color"],
                         "alpha": r["Alpha"]})

for case in range(12):
    pts = curve(2 + case)
    factor = 1.0 if case % 3 else f32(rng.uniform(0.0, 1.0))
    extend = ["HORIZONTAL", "EXTRAPOLATED"][case % 2]

    def make(tree, pos, pts=pts, factor=factor, extend=extend):
        n = tree.nodes.new("ShaderNodeFloatCurve")
        n.mapping.extend = extend
        set_points(n.mapping.curves[0], pts)
        n.mapping.update()
        pts[:] = [tuple(p.location) for p in n.mapping.curves[0].points]
        n.inputs["Factor"].default_value = factor
        sep = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(pos.outputs[0], sep.inputs[0])
        tree.links.new(sep.outputs[0], n.inputs["Value"])
        return n

    r = gn.evaluate(obj, make, [("Value", "FLOAT")])
    out["float_curves"].append({"points": pts, "factor": factor, "extend": extend.lower(),
                                "value": r["Value"]})

cols = [[f32(rng.uniform(-0.1, 1.1)) for _ in range(3)] for _ in range(N)]
cobj = gn.point_object(cols)
out["colors"] = cols
for case in range(6):
    cs = [curve(2 + (case + 3 * k) % 9) for k in range(4)]  # C, R, G, B
    fac = 1.0 if case % 2 else f32(rng.uniform(0.0, 1.0))
    extend = ["HORIZONTAL", "EXTRAPOLATED"][case // 3]

    def make(tree, pos, cs=cs, fac=fac, extend=extend):
        n = tree.nodes.new("ShaderNodeRGBCurve")
        n.mapping.extend = extend
        # Blender's curves are R, G, B, C; ours C, R, G, B.
        for cm, pts in zip([n.mapping.curves[3], n.mapping.curves[0], n.mapping.curves[1],
                            n.mapping.curves[2]], cs):
            set_points(cm, pts)
        n.mapping.update()
        cs[:] = [[tuple(p.location) for p in cm.points] for cm in [n.mapping.curves[3],
                 n.mapping.curves[0], n.mapping.curves[1], n.mapping.curves[2]]]
        n.inputs["Fac"].default_value = fac
        tree.links.new(pos.outputs[0], n.inputs["Color"])
        return n

    r = gn.evaluate(cobj, make, [("Color", "FLOAT_VECTOR")])
    out["rgb_curves"].append({"curves": cs, "fac": fac, "extend": extend.lower(),
                              "color": r["Color"]})

print(json.dumps(out))
