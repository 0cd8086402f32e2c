#!/usr/bin/env python3
"""An independent reader of locus' mesh outputs (tests/tools/independent_reader_cli.cpp).

Only Python's standard library: parses OBJ (v, vt, vn, f and the
'#locus vertex-properties' / '#vp' comment block), OFF and COFF, and PLY
(ascii and binary_little_endian, every scalar type, list faces), and prints
one JSON object: {"vertices": n, "faces": [[...], ...] or null, "properties":
{name: [values]}}, with vt as u, v, vn as nx, ny, nz and OFF colours as red,
green, blue (alpha). Written from the format descriptions, sharing nothing
with locus' C++ readers, so a test comparing the two finds a writer or reader
bug in either.

Usage: independent_reader.py FILE
"""
import json
import math
import struct
import sys

PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
    "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


def number(text):
    value = float(text)
    return value


def read_obj(text):
    positions, vts, vns, faces = [], [], [], []
    corner_vt, corner_vn = {}, {}
    block_names, block_rows = [], []
    for line in text.splitlines():
        parts = line.split()
        if not parts:
            continue
        kw = parts[0]
        if kw == "v":
            positions.append([float(x) for x in parts[1:4]])
        elif kw == "vt":
            vts.append([float(x) for x in parts[1:3]])
        elif kw == "vn":
            vns.append([float(x) for x in parts[1:4]])
        elif kw == "f":
            face = []
            for corner in parts[1:]:
                fields = corner.split("/")
                v = int(fields[0]) - 1
                face.append(v)
                if len(fields) > 1 and fields[1]:
                    corner_vt[v] = int(fields[1]) - 1
                if len(fields) > 2 and fields[2]:
                    corner_vn[v] = int(fields[2]) - 1
            faces.append(face)
        elif kw == "#locus" and len(parts) > 1 and parts[1] == "vertex-properties":
            block_names = [p.split(":")[0] for p in parts[2:]]
        elif kw == "#vp":
            block_rows.append([number(x) for x in parts[1:]])
    n = len(positions)
    props = {}
    if vts and len(corner_vt) == n:
        props["u"] = [vts[corner_vt[v]][0] for v in range(n)]
        props["v"] = [vts[corner_vt[v]][1] for v in range(n)]
    if vns and len(corner_vn) == n:
        for k, name in enumerate(("nx", "ny", "nz")):
            props[name] = [vns[corner_vn[v]][k] for v in range(n)]
    for k, name in enumerate(block_names):
        props[name] = [row[k] for row in block_rows]
    return n, faces, props


def read_off(text):
    tokens = []
    for line in text.splitlines():
        line = line.split("#", 1)[0]
        tokens.append(line.split())
    lines = [t for t in tokens if t]
    head = lines[0][0]
    colour = head.startswith("C")
    counts = lines[0][1:] if len(lines[0]) > 1 else lines[1]
    first = 1 if len(lines[0]) > 1 else 2
    nv, nf = int(counts[0]), int(counts[1])
    props = {}
    if colour:
        props = {"red": [], "green": [], "blue": [], "alpha": []}
    for row in lines[first:first + nv]:
        if colour:
            for name, x in zip(("red", "green", "blue", "alpha"), row[3:7]):
                props[name].append(float(x))
    faces = []
    for row in lines[first + nv:first + nv + nf]:
        k = int(row[0])
        faces.append([int(x) for x in row[1:1 + k]])
    props = {k: v for k, v in props.items() if v}
    return nv, faces, props


def read_ply(data):
    end = data.index(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = None
    elements = []
    for line in header:
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "format":
            fmt = parts[1]
        elif parts[0] == "element":
            elements.append({"name": parts[1], "count": int(parts[2]), "props": []})
        elif parts[0] == "property":
            if parts[1] == "list":
                elements[-1]["props"].append(("list", parts[2], parts[3], parts[4]))
            else:
                elements[-1]["props"].append(("scalar", parts[1], parts[2]))
    body = data[end:]
    n, faces, props = 0, [], {}
    if fmt == "ascii":
        tokens = body.decode("ascii").split()
        at = 0
        for el in elements:
            for _ in range(el["count"]):
                for p in el["props"]:
                    if p[0] == "list":
                        k = int(tokens[at]); at += 1
                        values = [int(x) for x in tokens[at:at + k]]; at += k
                        if el["name"] == "face":
                            faces.append(values)
                    else:
                        value = float(tokens[at]); at += 1
                        if el["name"] == "vertex":
                            props.setdefault(p[2], []).append(value)
            if el["name"] == "vertex":
                n = el["count"]
    elif fmt == "binary_little_endian":
        at = 0
        for el in elements:
            for _ in range(el["count"]):
                for p in el["props"]:
                    if p[0] == "list":
                        (k,) = struct.unpack_from("<" + PLY_TYPES[p[1]], body, at)
                        at += struct.calcsize(PLY_TYPES[p[1]])
                        code = "<%d%s" % (k, PLY_TYPES[p[2]])
                        values = list(struct.unpack_from(code, body, at))
                        at += struct.calcsize(code)
                        if el["name"] == "face":
                            faces.append(values)
                    else:
                        code = "<" + PLY_TYPES[p[1]]
                        (value,) = struct.unpack_from(code, body, at)
                        at += struct.calcsize(code)
                        if el["name"] == "vertex":
                            props.setdefault(p[2], []).append(float(value))
            if el["name"] == "vertex":
                n = el["count"]
    else:
        raise SystemExit("unsupported PLY format %r" % fmt)
    for coord in ("x", "y", "z"):
        props.pop(coord, None)
    return n, faces, props


def main():
    path = sys.argv[1]
    with open(path, "rb") as f:
        data = f.read()
    ext = path.rsplit(".", 1)[-1].lower()
    if ext == "obj":
        n, faces, props = read_obj(data.decode("utf-8"))
    elif ext == "off":
        n, faces, props = read_off(data.decode("utf-8"))
    elif ext == "ply":
        n, faces, props = read_ply(data)
    else:
        raise SystemExit("unknown extension " + ext)
    # JSON has no NaN: write it as null.
    clean = {k: [None if isinstance(x, float) and math.isnan(x) else x for x in v] for k, v in props.items()}
    json.dump({"vertices": n, "faces": faces, "properties": clean}, sys.stdout)


if __name__ == "__main__":
    main()
