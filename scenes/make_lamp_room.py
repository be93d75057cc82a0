#!/usr/bin/env python3
"""Writes lamp-room.gltf and lamp-room.glb, the small glTF 2.0 test scene of tests/test_import.c.

One unit quad (y = 0, facing +y) is used by every node, with node transforms placing it:
  floor   scaled 2 x 2                          area 4, faces +y, white (0.8 0.7 0.6)
  lamp    at y = 2, turned upside down          area 1, faces -y, emits (1 0.8 0.6) x 5
  stand/shelf  translation y 0.5, scale 0.4     area 0.16 at y = 0.5, faces +y (nested nodes)
  shelf   (again: imported as "shelf.2") at y = 1, scale y -1: a mirroring transform,
          so the face is turned and faces -y
  pane    KHR_materials_transmission 1, KHR_materials_ior 1.33 (glass)
  mirror  metallicFactor 1, roughnessFactor 0.2
  camera  at (0, 1, 4) looking along -z, yfov 0.8 rad, aspect 1.5
Run from this directory: python3 make_lamp_room.py
"""
import base64, json, math, struct

positions = [(-0.5, 0, -0.5), (-0.5, 0, 0.5), (0.5, 0, 0.5), (0.5, 0, -0.5)]
indices = [0, 1, 2, 0, 2, 3]  # two triangles, counter-clockwise seen from +y
binary = b"".join(struct.pack("<3f", *p) for p in positions)
binary += b"".join(struct.pack("<H", i) for i in indices)
binary += b"\0" * (-len(binary) % 4)

def document(buffer):
    s = math.sin(math.pi / 4)
    materials = [
        {"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1],
                                                   "metallicFactor": 0, "roughnessFactor": 1}},
        {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                  "metallicFactor": 0},
         "emissiveFactor": [1, 0.8, 0.6],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5}}},
        {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                                   "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                        "KHR_materials_ior": {"ior": 1.33}}},
        {"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                                                   "metallicFactor": 1, "roughnessFactor": 0.2}},
    ]
    meshes = [{"name": m["name"] + "-quad",
               "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": i}]}
              for i, m in enumerate(materials)]
    nodes = [
        {"name": "floor", "mesh": 0, "scale": [2, 1, 2]},
        {"name": "lamp", "mesh": 1, "translation": [0, 2, 0], "rotation": [1, 0, 0, 0]},
        {"name": "stand", "translation": [0, 0.5, 0], "children": [3]},
        {"name": "shelf", "mesh": 0, "scale": [0.4, 1, 0.4]},
        {"name": "shelf", "mesh": 0, "translation": [0, 1, 0], "scale": [1, -1, 1]},
        {"name": "pane", "mesh": 2, "translation": [0, 1, -0.9], "rotation": [s, 0, 0, s]},
        {"name": "mirror", "mesh": 3, "translation": [0.9, 1, 0], "rotation": [0, 0, s, s]},
        {"name": "camera", "camera": 0, "translation": [0, 1, 4]},
    ]
    return {
        "asset": {"version": "2.0", "generator": "radiosity scenes/make_lamp_room.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_transmission",
                           "KHR_materials_ior"],
        "buffers": [buffer],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-0.5, 0, -0.5], "max": [0.5, 0, 0.5]},
                      {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "materials": materials,
        "meshes": meshes,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}],
        "nodes": nodes,
        "scenes": [{"nodes": [0, 1, 2, 4, 5, 6, 7]}],
        "scene": 0,
    }

uri = "data:application/octet-stream;base64," + base64.b64encode(binary).decode()
with open("lamp-room.gltf", "w") as f:
    json.dump(document({"byteLength": len(binary), "uri": uri}), f, indent=1)
    f.write("\n")

text = json.dumps(document({"byteLength": len(binary)})).encode()
text += b" " * (-len(text) % 4)
chunks = struct.pack("<I4s", len(text), b"JSON") + text
chunks += struct.pack("<I4s", len(binary), b"BIN\0") + binary
with open("lamp-room.glb", "wb") as f:
    f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)
