#!/usr/bin/env python3
"""Writes a unit UV sphere as a binary glTF (.glb): the tessellation of the scene files' built-in
sphere (engine/scene/meshes.cpp: a pole, segments/2 - 1 rings of `segments` vertices, a pole), so
segments S gives S * (S - 2) triangles. The built-in sphere stops at segments 3000 (9 M triangles);
this makes larger single meshes for the load-time measurements of docs/PERFORMANCE.md ("Large
models"), e.g. segments 4474 for 20 M triangles.

    scripts/make-sphere-glb.py 4474 /tmp/sphere20m.glb
    build/app/envshadow render --scene /tmp/sphere20m.glb --width 64 --height 48 --lights 16 --msaa 1 --out /tmp/s.png
"""
import argparse
import json
import math
import struct
from array import array


def sphere(segments):
    bands = max(2, segments // 2)
    normals = array("f", [0.0, 1.0, 0.0])
    ring_phis = [2.0 * math.pi * j / segments for j in range(segments)]
    cos_phi = [math.cos(p) for p in ring_phis]
    sin_phi = [math.sin(p) for p in ring_phis]
    for i in range(1, bands):
        theta = math.pi * i / bands
        s, c = math.sin(theta), math.cos(theta)
        ring = array("f", [0.0]) * (3 * segments)
        ring[0::3] = array("f", [s * x for x in cos_phi])
        ring[1::3] = array("f", [c]) * segments
        ring[2::3] = array("f", [s * z for z in sin_phi])
        normals.extend(ring)
    normals.extend([0.0, -1.0, 0.0])

    def ring_index(i, j):
        return 1 + (i - 1) * segments + j % segments

    south = len(normals) // 3 - 1
    indices = array("I")
    for j in range(segments):
        indices.extend((0, ring_index(1, j + 1), ring_index(1, j)))
    for i in range(1, bands - 1):
        u0 = array("I", range(ring_index(i, 0), ring_index(i, 0) + segments))
        u1 = array("I", [ring_index(i, j + 1) for j in range(segments)])
        l0 = array("I", [x + segments for x in u0])
        l1 = array("I", [x + segments for x in u1])
        quad = array("I", [0]) * (6 * segments)
        for k, column in enumerate((u0, u1, l1, u0, l1, l0)):
            quad[k::6] = column
        indices.extend(quad)
    for j in range(segments):
        indices.extend((south, ring_index(bands - 1, j), ring_index(bands - 1, j + 1)))
    return normals, indices


def write_glb(path, normals, indices):
    vertex_bytes = normals.tobytes()
    index_bytes = indices.tobytes()
    vertex_count = len(normals) // 3
    buffer = vertex_bytes + index_bytes
    gltf = {
        "asset": {"version": "2.0", "generator": "envshadow scripts/make-sphere-glb.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(buffer)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(vertex_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(vertex_bytes), "byteLength": len(index_bytes), "target": 34963},
        ],
        "accessors": [
            # A unit sphere's positions are its normals.
            {"bufferView": 0, "componentType": 5126, "count": vertex_count, "type": "VEC3",
             "min": [-1.0, -1.0, -1.0], "max": [1.0, 1.0, 1.0]},
            {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    buffer += b"\0" * (-len(buffer) % 4)
    with open(path, "wb") as out:
        out.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(buffer)))
        out.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        out.write(struct.pack("<II", len(buffer), 0x004E4942) + buffer)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("segments", type=int, help="segments around the equator (4 or more)")
    parser.add_argument("out", help="the .glb to write")
    args = parser.parse_args()
    if args.segments < 4:
        parser.error("segments must be 4 or more")
    normals, indices = sphere(args.segments)
    write_glb(args.out, normals, indices)
    print(f"{args.out}: {len(normals) // 3} vertices, {len(indices) // 3} triangles")


if __name__ == "__main__":
    main()
