#!/usr/bin/env python3
"""Independent check for tests/scene/gltf_test.cpp: world-space bounds of every vertex referenced by a
triangle primitive of a .glb's default scene, with node matrices / TRS applied. Pure Python (no numpy),
written apart from the C++ loader so the test's expected numbers do not come from the code under test.

    tests/scene/tools/gltf_world_bounds.py /usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
"""
import json
import struct
import sys


def mat_mul(a, b):  # 4x4, row-major lists
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[0][0] * sx, r[0][1] * sy, r[0][2] * sz, tx],
            [r[1][0] * sx, r[1][1] * sy, r[1][2] * sz, ty],
            [r[2][0] * sx, r[2][1] * sy, r[2][2] * sz, tz],
            [0, 0, 0, 1]]


def main(path):
    data = open(path, "rb").read()
    json_length = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + json_length])
    bin_offset = 20 + json_length + 8
    lo = [float("inf")] * 3
    hi = [float("-inf")] * 3
    triangles = 0

    def accessor_values(index, width, fmt):
        acc = doc["accessors"][index]
        view = doc["bufferViews"][acc["bufferView"]]
        stride = view.get("byteStride", struct.calcsize("<" + fmt) * width)
        start = bin_offset + view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        return [struct.unpack_from("<" + fmt * width, data, start + i * stride) for i in range(acc["count"])]

    def visit(node_index, parent):
        nonlocal triangles
        node = doc["nodes"][node_index]
        world = mat_mul(parent, node_matrix(node))
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    continue
                positions = accessor_values(prim["attributes"]["POSITION"], 3, "f")
                if "indices" in prim:
                    ctype = doc["accessors"][prim["indices"]]["componentType"]
                    fmt = {5121: "B", 5123: "H", 5125: "I"}[ctype]
                    used = sorted({i[0] for i in accessor_values(prim["indices"], 1, fmt)})
                    triangles += doc["accessors"][prim["indices"]]["count"] // 3
                else:
                    used = range(len(positions))
                    triangles += len(positions) // 3
                for i in used:
                    p = positions[i]
                    for r in range(3):
                        v = sum(world[r][c] * p[c] for c in range(3)) + world[r][3]
                        lo[r] = min(lo[r], v)
                        hi[r] = max(hi[r], v)
        for child in node.get("children", []):
            visit(child, world)

    identity = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(root, identity)
    print("triangles", triangles)
    print("min", " ".join("%.4f" % v for v in lo))
    print("max", " ".join("%.4f" % v for v in hi))


if __name__ == "__main__":
    main(sys.argv[1])
