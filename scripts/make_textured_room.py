#!/usr/bin/env python3
"""Writes a textured glTF 2.0 room, the test scene for textures (docs/rendering.md, "Textures").

usage: make_textured_room.py OUT.gltf [--embed] [--texture NAME.png] [--size N]

A closed room 4 m wide (x), 3 m high (y), 4 m deep (z), every face turned inwards:
  floor    checker of 8 x 8 squares, red (200 40 30) and cream (235 225 205), sRGB; the first
           row of squares along the back wall (z = 0) is green (40 160 60) instead of red, so
           that a flipped texture shows; colour factor 0.9
  walls, ceiling   white 0.75 (no texture)
  lamp     1 x 1 m at the ceiling's centre, facing down, emitted radiance 10
  camera   at (2, 2.2, 3.9) looking along -z turned 30 degrees down, yfov 1.0 rad, aspect 1
The texture is a PNG of N x N texels (default 64) written beside OUT.gltf (default name
checker.png), or with --embed put in the glTF's own buffer (an embedded image). Only the
standard library is used (zlib for the PNG)."""
import base64
import json
import os
import struct
import sys
import zlib


def png(width, height, rows):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + bytes(row) for row in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker(size):
    red, cream, green = (200, 40, 30), (235, 225, 205), (40, 160, 60)
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            i, j = 8 * x // size, 8 * y // size
            colour = cream if (i + j) % 2 else (green if j == 0 else red)
            row.extend(colour)
        rows.append(row)
    return png(size, size, rows)


def quad(corners, normal):
    """Corners in order, turned so that they run counter-clockwise seen from `normal`."""
    a, b, c = corners[0], corners[1], corners[2]
    e1 = [b[k] - a[k] for k in range(3)]
    e2 = [c[k] - a[k] for k in range(3)]
    n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    return corners if sum(n[k] * normal[k] for k in range(3)) > 0 else corners[::-1]


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        sys.exit(__doc__)
    out, embed, name, size = args[0], "--embed" in args, "checker.png", 64
    if "--texture" in args:
        name = args[args.index("--texture") + 1]
    if "--size" in args:
        size = int(args[args.index("--size") + 1])
    W, H, D = 4.0, 3.0, 4.0
    # The floor: glTF texture coordinates have (0, 0) at the image's top left; v = 0 at z = 0.
    objects = [
        ("floor", quad([(0, 0, 0), (0, 0, D), (W, 0, D), (W, 0, 0)], (0, 1, 0)), 0),
        ("ceiling", quad([(0, H, 0), (W, H, 0), (W, H, D), (0, H, D)], (0, -1, 0)), 1),
        ("back", quad([(0, 0, 0), (W, 0, 0), (W, H, 0), (0, H, 0)], (0, 0, 1)), 1),
        ("front", quad([(0, 0, D), (0, H, D), (W, H, D), (W, 0, D)], (0, 0, -1)), 1),
        ("left", quad([(0, 0, 0), (0, H, 0), (0, H, D), (0, 0, D)], (1, 0, 0)), 1),
        ("right", quad([(W, 0, 0), (W, 0, D), (W, H, D), (W, H, 0)], (-1, 0, 0)), 1),
        ("lamp", quad([(1.5, H - 0.01, 1.5), (2.5, H - 0.01, 1.5), (2.5, H - 0.01, 2.5),
                       (1.5, H - 0.01, 2.5)], (0, -1, 0)), 2),
    ]
    binary, views, accessors, meshes, nodes = b"", [], [], [], []

    def add(data, **accessor):
        nonlocal binary
        views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
        binary += data + b"\0" * (-len(data) % 4)
        if accessor:
            accessor["bufferView"] = len(views) - 1
            accessors.append(accessor)
            return len(accessors) - 1
        return len(views) - 1

    for name_, corners, material in objects:
        position = add(b"".join(struct.pack("<3f", *p) for p in corners), componentType=5126,
                       count=4, type="VEC3", min=[min(p[k] for p in corners) for k in range(3)],
                       max=[max(p[k] for p in corners) for k in range(3)])
        index = add(struct.pack("<6H", 0, 1, 2, 0, 2, 3), componentType=5123, count=6,
                    type="SCALAR")
        attributes = {"POSITION": position}
        if name_ == "floor":
            uv = [(p[0] / W, p[2] / D) for p in corners]
            attributes["TEXCOORD_0"] = add(b"".join(struct.pack("<2f", *t) for t in uv),
                                           componentType=5126, count=4, type="VEC2")
        meshes.append({"name": name_, "primitives": [
            {"attributes": attributes, "indices": index, "material": material}]})
        nodes.append({"name": name_, "mesh": len(meshes) - 1})
    # Turned 30 degrees down about x.
    nodes.append({"name": "camera", "camera": 0, "translation": [2, 2.2, 3.9],
                  "rotation": [-0.25881904510252074, 0, 0, 0.9659258262890683]})
    image_bytes = checker(size)
    if embed:
        image = {"bufferView": add(image_bytes), "mimeType": "image/png"}
    else:
        with open(os.path.join(os.path.dirname(out) or ".", name), "wb") as f:
            f.write(image_bytes)
        image = {"uri": name}
    plain = lambda c: {"baseColorFactor": c, "metallicFactor": 0, "roughnessFactor": 1}
    document = {
        "asset": {"version": "2.0", "generator": "radiosity scripts/make_textured_room.py"},
        "buffers": [{"byteLength": len(binary),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(binary).decode()}],
        "bufferViews": views,
        "accessors": accessors,
        "images": [image],
        "samplers": [{"magFilter": 9729, "minFilter": 9729}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [
            {"name": "checker", "pbrMetallicRoughness": dict(plain([0.9, 0.9, 0.9, 1]),
                                                             baseColorTexture={"index": 0})},
            {"name": "white", "pbrMetallicRoughness": plain([0.75, 0.75, 0.75, 1])},
            {"name": "lamp", "pbrMetallicRoughness": plain([0.5, 0.5, 0.5, 1]),
             "emissiveFactor": [1, 1, 1],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10}}},
        ],
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "meshes": meshes,
        "nodes": nodes,
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.0, "aspectRatio": 1, "znear": 0.05}}],
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "scene": 0,
    }
    with open(out, "w") as f:
        json.dump(document, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
