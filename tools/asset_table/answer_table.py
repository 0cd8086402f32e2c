#!/usr/bin/env python3
"""The table "answered / readable": which meshes every command answers on.

For every mesh file under the given folders that `locus info` reads (asset
files read directly in their own format through assimp, with at least
--min-vertices vertices; OFF/OBJ/PLY files whatever their size), runs

  geodesic --source 0, voronoi --random 8, skinweights --handles (4 vertices),
  cvt --sites 200 --iters 2 (labels)

(site and handle counts capped at the mesh's referenced vertices) with the
default --operator auto, and counts per command and per folder the files it
answered on (exit 0). Each failure is listed with its exit status and message.
Files without faces (point clouds, line sets) are counted apart: they have no
surface for these commands. With --convert, every asset file is also converted
to OBJ first (`assimp export FILE OUT.obj -ptv -jiv -tri`, the assimp-utils
package) and the OBJ run the same way. Usage:

  python3 tools/asset_table/answer_table.py --locus build/locus \\
      --dir /usr/share/assimp/models --min-vertices 500 --dir cache/meshes --out docs/robust_table.md
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

COMMANDS = {  # each command's options for a mesh of n referenced vertices
    "geodesic": lambda n: ["--source", "0"],
    "voronoi": lambda n: ["--random", str(min(8, n))],
    "skinweights": lambda n: ["--handles", ",".join(str(v) for v in sorted({0, n // 4, n // 2, 3 * n // 4}))],
    "cvt": lambda n: ["--sites", str(min(200, n)), "--iters", "2"],
}
OWN = {"off", "obj", "ply"}
SKIP = {"txt", "png", "jpg", "jpeg", "tga", "bmp", "dds", "mtl", "bin", "glsl", "xml", "md", "json", "html", "zip",
        "gz", "c", "h", "py", "pdf", "psd", "tif", "tiff", "gif", "hdr", "exr", "ktx", "ktx2", "mat", "shader"}


def run(locus, args, timeout):
    try:
        p = subprocess.run([locus] + args + ["--threads", "1", "--json"], capture_output=True, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return 124, "timeout", None
    out = None
    if p.returncode == 0:
        try:
            out = json.loads(p.stdout)
        except ValueError:
            pass
    err = p.stderr.strip().splitlines()
    return p.returncode, (err[-1] if err else ""), out


def files_under(folder):
    for root, _, names in os.walk(folder):
        for name in sorted(names):
            ext = name.rsplit(".", 1)[-1].lower() if "." in name else ""
            if ext and ext not in SKIP:
                yield os.path.join(root, name), ext


def mesh_size(locus, path, timeout):
    """(referenced vertices, faces) of a file `locus info` reads, else None."""
    st, _, info = run(locus, ["info", path], timeout)
    if st != 0 or not info:
        return None
    return info["n_vertices"] - info.get("unreferenced_vertices", 0), info["n_faces"]


def convert_to_obj(path, tmp):
    """The issue's conversion: assimp export FILE OUT.obj -ptv -jiv -tri; the OBJ's path or None."""
    out = os.path.join(tmp, os.path.basename(path).replace(".", "_") + ".obj")
    try:
        p = subprocess.run(["assimp", "export", path, out, "-ptv", "-jiv", "-tri"], capture_output=True, timeout=300)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return out if p.returncode == 0 and os.path.exists(out) else None


def answer(a, path, n, tmp, counts, failures):
    status = []
    for c, args in COMMANDS.items():
        out = ["-o", os.path.join(tmp, "out.ply")] if c == "geodesic" else []  # cvt: labels only
        st, msg, _ = run(a.locus, [c, path] + args(n) + out, a.timeout)
        status.append(f"{c}={st}")
        if st == 0:
            counts[c] += 1
        else:
            failures.append(f"{c} {path}: exit {st}: {msg}")
    print(f"{path}: {n} vertices: {' '.join(status)}", file=sys.stderr, flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--locus", default="build/locus")
    ap.add_argument("--dir", action="append", required=True, help="folder of meshes (repeatable)")
    ap.add_argument("--min-vertices", type=int, action="append", default=[],
                    help="per --dir, in order: asset files with fewer vertices are left out (default 0)")
    ap.add_argument("--convert", action="store_true", help="also run every asset file converted to OBJ by assimp")
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--out", help="Markdown file for the table (default: stdout only)")
    a = ap.parse_args()
    lines = ["| files | command | answered / readable |", "|---|---|---|"]
    failures, no_surface = [], []
    for k, folder in enumerate(a.dir):
        minv = a.min_vertices[k] if k < len(a.min_vertices) else 0
        with tempfile.TemporaryDirectory() as tmp:
            groups = {"own format": [], "converted to OBJ": []}
            for path, ext in files_under(folder):
                size = mesh_size(a.locus, path, a.timeout)
                if size is None or (ext not in OWN and size[0] < minv):
                    continue
                if size[1] == 0:
                    no_surface.append(path)
                    continue
                groups["own format"].append((path, size[0]))
                if a.convert and ext not in OWN:
                    obj = convert_to_obj(path, tmp)
                    size_obj = mesh_size(a.locus, obj, a.timeout) if obj else None
                    if size_obj and size_obj[1] > 0:
                        groups["converted to OBJ"].append((obj, size_obj[0]))
            for group, files in groups.items():
                if not files:
                    continue
                counts = {c: 0 for c in COMMANDS}
                for path, n in files:
                    answer(a, path, n, tmp, counts, failures)
                for c in COMMANDS:
                    lines.append(f"| {folder}, {group} (>= {minv} vertices for asset files) | {c} | "
                                 f"{counts[c]} / {len(files)} |")
    text = "\n".join(lines) + "\n\nFailures:\n\n" + ("\n".join("- " + f for f in failures) or "- none") + "\n"
    text += "\nReadable files without faces (point clouds, line sets; no surface):\n\n" + \
        ("\n".join("- " + f for f in no_surface) or "- none") + "\n"
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
