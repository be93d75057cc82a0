#!/usr/bin/env python3
"""make_light_room.py - writes scenes/lights-room.gltf: a closed 4 x 3 x 4 room with a box on its
floor, lit only by a KHR_lights_punctual point light and spot light (docs/lights.md). The glTF is
self-contained (the buffer is a data URI). Usage: scenes/make_light_room.py [OUT.gltf]"""
import base64, json, struct, sys

def quad(a, b, c, d, normal):
    """Two triangles of the quad a b c d, wound counter-clockwise seen from `normal`'s side."""
    e1 = [b[i] - a[i] for i in range(3)]
    e2 = [c[i] - a[i] for i in range(3)]
    n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    if sum(n[i] * normal[i] for i in range(3)) < 0:
        a, b, c, d = a, d, c, b
    return [a, b, c, d]

def box_faces(lo, hi, inward):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    s = -1 if inward else 1
    return [
        quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), (0, -s, 0)),
        quad((x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1), (0, s, 0)),
        quad((x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1), (-s, 0, 0)),
        quad((x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1), (s, 0, 0)),
        quad((x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (0, 0, -s)),
        quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (0, 0, s)),
    ]

room = box_faces((0, 0, 0), (4, 3, 4), True)
# floor, ceiling, walls -x, +x, -z, +z: the room's floor is its face 0; the box has no bottom.
box = box_faces((0.8, 0, 2.2), (1.8, 1.2, 3.2), False)[1:]
meshes = [("floor", [room[0]], 0), ("ceiling", [room[1]], 1), ("walls", room[2:6], 1),
          ("box", box, 2)]
materials = [("floor", [0.5, 0.5, 0.5]), ("white", [0.7, 0.7, 0.7]), ("red", [0.7, 0.25, 0.2])]

data = bytearray()
accessors, views, gltf_meshes = [], [], []
for name, quads, material in meshes:
    positions = [p for q in quads for p in q]
    indices = []
    for k in range(len(quads)):
        indices += [4 * k, 4 * k + 1, 4 * k + 2, 4 * k, 4 * k + 2, 4 * k + 3]
    start = len(data)
    for p in positions:
        data += struct.pack("<3f", *p)
    views.append({"buffer": 0, "byteOffset": start, "byteLength": len(data) - start})
    lo = [min(p[i] for p in positions) for i in range(3)]
    hi = [max(p[i] for p in positions) for i in range(3)]
    accessors.append({"bufferView": len(views) - 1, "componentType": 5126, "count": len(positions),
                      "type": "VEC3", "min": lo, "max": hi})
    start = len(data)
    for i in indices:
        data += struct.pack("<H", i)
    while len(data) % 4:
        data += b"\0"
    views.append({"buffer": 0, "byteOffset": start, "byteLength": 2 * len(indices)})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": len(indices),
                      "type": "SCALAR"})
    gltf_meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": len(accessors) - 2},
                                                       "indices": len(accessors) - 1,
                                                       "material": material}]})

# Intensities in candela: 179 cd is 1 W/sr at 179 lm/W (docs/units.md).
lights = [{"name": "bulb", "type": "point", "color": [1.0, 0.9, 0.8], "intensity": 179.0},
          {"name": "spot", "type": "spot", "color": [0.8, 0.9, 1.0], "intensity": 537.0,
           "spot": {"innerConeAngle": 0.35, "outerConeAngle": 0.52}}]
nodes = [{"name": name, "mesh": i} for i, (name, _, _) in enumerate(meshes)]
nodes.append({"name": "bulb", "translation": [1.2, 2.5, 1.0],
              "extensions": {"KHR_lights_punctual": {"light": 0}}})
# The spot looks down: its local -Z turned onto -Y (-90 degrees about X).
nodes.append({"name": "spot", "translation": [2.8, 2.9, 2.6],
              "rotation": [-0.7071067811865476, 0, 0, 0.7071067811865476],
              "extensions": {"KHR_lights_punctual": {"light": 1}}})
gltf = {
    "asset": {"version": "2.0", "generator": "scenes/make_light_room.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": lights}},
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "nodes": nodes,
    "meshes": gltf_meshes,
    "materials": [{"name": n, "pbrMetallicRoughness": {"baseColorFactor": c + [1.0],
                                                        "metallicFactor": 0.0}}
                  for n, c in materials],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(data),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode()}],
}
out = sys.argv[1] if len(sys.argv) > 1 else "scenes/lights-room.gltf"
with open(out, "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
