"""Reference values of Blender's Wave, Brick and Magic Texture nodes, evaluated by Blender
itself (as tests/blender/noise_reference.py, through geometry nodes):

    python tests/blender/wave_brick_magic_reference.py > tests/blender/wave_brick_magic.json

Points are f32-exact. Brick's tint jumps at every row and brick edge (and its mortar at the
mortar's edge where mortar_smooth is 0): a point is kept only where, in every brick case, it
lies at least MARGIN (in scaled units, f64) from each of them, so that rounding cannot put it
in another brick than Blender's.
"""
import json
import math
import random
import struct

import bpy

import gn

MARGIN = 1e-3


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


WAVE = [
    # type, bands direction, rings direction, profile, scale, distortion, detail,
    # detail scale, detail roughness, phase offset
    ("BANDS", "X", "X", "SIN", 5.0, 0.0, 2.0, 1.0, 0.5, 0.0),
    ("BANDS", "Y", "X", "SAW", 3.0, 0.0, 2.0, 1.0, 0.5, 1.3),
    ("BANDS", "Z", "X", "TRI", 2.5, 0.0, 2.0, 1.0, 0.5, 0.0),
    ("BANDS", "DIAGONAL", "X", "SIN", 4.0, 2.5, 3.0, 1.5, 0.6, 0.0),
    ("BANDS", "X", "X", "SAW", 2.0, 10.0, 0.0, 1.0, 0.5, 0.0),
    ("RINGS", "X", "X", "SIN", 2.0, 0.0, 2.0, 1.0, 0.5, 0.0),
    ("RINGS", "X", "Y", "SAW", 3.0, 1.0, 2.5, 1.0, 0.5, 0.0),
    ("RINGS", "X", "Z", "TRI", 1.5, 0.0, 2.0, 1.0, 0.5, 0.7),
    ("RINGS", "X", "SPHERICAL", "SIN", 3.0, 4.0, 6.0, 0.7, 0.45, -2.0),
    ("RINGS", "X", "SPHERICAL", "TRI", 2.0, -3.0, 1.5, 2.0, 0.8, 0.0),
]

BRICK = [
    # color1, color2, mortar, scale, mortar size, mortar smooth, bias, brick width,
    # row height, offset, offset frequency, squash, squash frequency
    ((0.8, 0.1, 0.1), (0.1, 0.6, 0.9), (0.05, 0.05, 0.05), 5.0, 0.02, 0.1, 0.0, 0.5, 0.25,
     0.5, 2, 1.0, 2),
    ((0.9, 0.7, 0.2), (0.2, 0.3, 0.4), (0.6, 0.6, 0.55), 2.0, 0.05, 0.5, 0.3, 0.7, 0.3,
     0.25, 3, 1.7, 2),
    ((0.3, 0.8, 0.3), (0.7, 0.2, 0.6), (1.0, 1.0, 1.0), 3.0, 0.1, 0.0, -0.4, 0.5, 0.25,
     0.8, 1, 0.6, 3),
    ((0.5, 0.5, 0.5), (0.0, 0.0, 1.0), (0.0, 0.0, 0.0), 8.0, 0.0, 0.1, 0.9, 0.5, 0.25,
     0.5, 2, 1.0, 2),
    ((0.1, 0.2, 0.3), (0.9, 0.8, 0.7), (0.4, 0.0, 0.0), 1.3, 0.03, 0.3, 0.1, 0.4, 0.2,
     0.0, 2, 2.5, 1),
]

MAGIC = [
    # depth, scale, distortion
    (0, 5.0, 1.0),
    (1, 2.5, 2.0),
    (2, 5.0, 1.0),
    (3, 1.7, -1.5),
    (4, 3.0, 0.5),
    (5, 0.8, 2.0),
    (6, 2.0, 1.2),
    (7, 1.5, 0.8),
    (8, 2.0, 1.0),
    (9, 1.0, 0.7),
    (10, 2.0, 1.0),
    (10, 5.0, 0.0),
    (10, 1.5, -2.0),
]


def brick_clear(p, case):
    """Whether `p` is at least MARGIN from every discontinuity of the brick `case` (f64)."""
    _, _, _, scale, size, smooth, _, width, height, offset, ofreq, squash, sfreq = case
    x, y = p[0] * scale, p[1] * scale
    row = math.floor(y / height)
    if row % sfreq == 0:
        width *= squash
    shift = width * offset if row % ofreq == 0 else 0.0
    brick = math.floor((x + shift) / width)
    bx = x + shift - width * brick
    by = y - height * row
    edges = min(bx, by, width - bx, height - by)
    if edges < MARGIN:
        return False
    return not (smooth == 0.0 and abs(edges - size) < MARGIN)


rng = random.Random(3636)
candidates = [(0.03, 0.11, 0.0), (0.37, -0.41, 0.5), (-0.83, 0.57, 0.0), (1.11, -1.13, 0.5),
              (0.61, 0.19, -0.5), (-0.29, 0.03, 1.0)]
candidates += [tuple(rng.uniform(-1.5, 1.5) for _ in range(3)) for _ in range(400)]
points = []
for c in candidates:
    p = tuple(f32(v) for v in c)
    if all(brick_clear(p, case) for case in BRICK):
        points.append(p)
    if len(points) == 64:
        break

obj = gn.point_object(points)
OUTPUTS = [("Color", "FLOAT_VECTOR"), ("Fac", "FLOAT")]

out = {"blender": bpy.app.version_string, "points": [list(p) for p in points],
       "brick_margin": MARGIN, "wave": [], "brick": [], "magic": []}

for case in WAVE:
    kind, bands, rings, profile, scale, dist, detail, dscale, drough, phase = case

    def make(tree, pos):
        n = tree.nodes.new("ShaderNodeTexWave")
        n.wave_type, n.bands_direction, n.rings_direction, n.wave_profile = kind, bands, rings, profile
        tree.links.new(pos.outputs[0], n.inputs["Vector"])
        for name, v in (("Scale", scale), ("Distortion", dist), ("Detail", detail),
                        ("Detail Scale", dscale), ("Detail Roughness", drough),
                        ("Phase Offset", phase)):
            n.inputs[name].default_value = v
        return n

    r = gn.evaluate(obj, make, OUTPUTS)
    out["wave"].append({
        "type": kind, "bands_direction": bands, "rings_direction": rings, "profile": profile,
        "scale": scale, "distortion": dist, "detail": detail, "detail_scale": dscale,
        "detail_roughness": drough, "phase_offset": phase, "color": r["Color"], "fac": r["Fac"],
    })

for case in BRICK:
    c1, c2, mortar, scale, size, smooth, bias, width, height, offset, ofreq, squash, sfreq = case

    def make(tree, pos):
        n = tree.nodes.new("ShaderNodeTexBrick")
        n.offset, n.offset_frequency, n.squash, n.squash_frequency = offset, ofreq, squash, sfreq
        tree.links.new(pos.outputs[0], n.inputs["Vector"])
        for name, v in (("Color1", c1), ("Color2", c2), ("Mortar", mortar)):
            n.inputs[name].default_value = (*v, 1.0)
        for name, v in (("Scale", scale), ("Mortar Size", size), ("Mortar Smooth", smooth),
                        ("Bias", bias), ("Brick Width", width), ("Row Height", height)):
            n.inputs[name].default_value = v
        return n

    r = gn.evaluate(obj, make, OUTPUTS)
    out["brick"].append({
        "color1": c1, "color2": c2, "mortar": mortar, "scale": scale, "mortar_size": size,
        "mortar_smooth": smooth, "bias": bias, "brick_width": width, "row_height": height,
        "offset": offset, "offset_frequency": ofreq, "squash": squash,
        "squash_frequency": sfreq, "color": r["Color"], "fac": r["Fac"],
    })

for depth, scale, dist in MAGIC:
    def make(tree, pos):
        n = tree.nodes.new("ShaderNodeTexMagic")
        n.turbulence_depth = depth
        tree.links.new(pos.outputs[0], n.inputs["Vector"])
        n.inputs["Scale"].default_value = scale
        n.inputs["Distortion"].default_value = dist
        return n

    r = gn.evaluate(obj, make, OUTPUTS)
    out["magic"].append({"depth": depth, "scale": scale, "distortion": dist,
                         "color": r["Color"], "fac": r["Fac"]})
print(json.dumps(out))
