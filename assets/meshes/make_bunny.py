#!/usr/bin/env python3
"""Writes bunny.obj: a bunny-like closed surface made here, procedurally (no third-party
data): the zero level set of a smooth union (soft minimum) of ellipsoids - body, head, two
ears, tail, four feet - extracted by marching tetrahedra on an N^3 lattice (six tetrahedra
per cube around the main diagonal, so neighbouring cubes agree and the surface is closed
and watertight; vertices shared per lattice edge). Fits the unit cube [0, 1]^3, +y up.
    python3 assets/meshes/make_bunny.py [N] > assets/meshes/bunny.obj
    python3 assets/meshes/make_bunny.py --silhouette [N] > assets/meshes/bunny_silhouette.png
The silhouette (2D keyframes) is the side view: a pixel (x, y) is white when the field is
negative somewhere along z (8-bit grey PNG, N x N, y up in the scene so the rows are
written top (y = 1) first).
"""
import math
import struct
import sys
import zlib

# (center, semi-axes) in the unit cube, y up, bunny facing +x.
ELLIPSOIDS = [
    ((0.45, 0.36, 0.50), (0.26, 0.20, 0.19)),  # body
    ((0.70, 0.52, 0.50), (0.13, 0.12, 0.115)),  # head
    ((0.72, 0.76, 0.44), (0.045, 0.17, 0.055)),  # left ear
    ((0.61, 0.77, 0.56), (0.045, 0.17, 0.055)),  # right ear
    ((0.18, 0.42, 0.50), (0.06, 0.06, 0.06)),  # tail
    ((0.60, 0.19, 0.40), (0.09, 0.05, 0.055)),  # front feet
    ((0.60, 0.19, 0.60), (0.09, 0.05, 0.055)),
    ((0.33, 0.19, 0.36), (0.13, 0.06, 0.07)),  # hind feet
    ((0.33, 0.19, 0.64), (0.13, 0.06, 0.07)),
]
SOFTNESS = 0.02  # smooth-minimum width (blends the parts into one surface)


def field(x, y, z):
    """Signed (approximate) distance: < 0 inside."""
    s = 0.0
    for (cx, cy, cz), (ax, ay, az) in ELLIPSOIDS:
        q = math.sqrt(((x - cx) / ax) ** 2 + ((y - cy) / ay) ** 2 + ((z - cz) / az) ** 2)
        d = (q - 1.0) * min(ax, ay, az)
        s += math.exp(-d / SOFTNESS)
    return -SOFTNESS * math.log(s)


def silhouette(n):
    rows = []
    for j in reversed(range(n)):
        y = (j + 0.5) / n
        row = bytearray([0])  # PNG filter type 0 per row
        for i in range(n):
            x = (i + 0.5) / n
            inside = any(field(x, y, (k + 0.5) / 32) < 0 for k in range(32))
            row.append(255 if inside else 0)
        rows.append(bytes(row))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
    sys.stdout.buffer.write(png)


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--silhouette":
        silhouette(int(sys.argv[2]) if len(sys.argv) > 2 else 128)
        return
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    h = 1.0 / n
    p = lambda i, j, k: (i * h, j * h, k * h)
    val = {}
    for i in range(n + 1):
        for j in range(n + 1):
            for k in range(n + 1):
                val[(i, j, k)] = field(*p(i, j, k))
    verts, index, tris = [], {}, []

    def vertex(a, b):  # crossing on lattice edge a-b
        key = (a, b) if a < b else (b, a)
        if key not in index:
            fa, fb = val[a], val[b]
            t = fa / (fa - fb)
            pa, pb = p(*a), p(*b)
            verts.append(tuple(pa[c] + t * (pb[c] - pa[c]) for c in range(3)))
            index[key] = len(verts)  # OBJ indices are 1-based
        return index[key]

    def emit(tri, inside_pt):
        a, b, c = (verts[v - 1] for v in tri)
        u = [b[i] - a[i] for i in range(3)]
        w = [c[i] - a[i] for i in range(3)]
        nrm = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        to_in = [inside_pt[i] - a[i] for i in range(3)]
        if sum(nrm[i] * to_in[i] for i in range(3)) > 0:  # outward normals
            tri = (tri[0], tri[2], tri[1])
        tris.append(tri)

    # Six tetrahedra per cube, all containing the diagonal corner 0 - corner 7.
    corners = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 1)]
    tets = [(0, 1, 3, 7), (0, 3, 2, 7), (0, 2, 6, 7), (0, 6, 4, 7), (0, 4, 5, 7), (0, 5, 1, 7)]
    for i in range(n):
        for j in range(n):
            for k in range(n):
                cube = [(i + c[0], j + c[1], k + c[2]) for c in corners]
                for t in tets:
                    v = [cube[x] for x in t]
                    ins = [x for x in v if val[x] < 0]
                    out = [x for x in v if val[x] >= 0]
                    if not ins or not out:
                        continue
                    inside_pt = p(*ins[0])
                    if len(ins) == 1 or len(out) == 1:
                        lone, rest = (ins[0], out) if len(ins) == 1 else (out[0], ins)
                        emit(tuple(vertex(lone, r) for r in rest), inside_pt)
                    else:  # two and two: a quad, split in two triangles
                        a, b = ins
                        c, d = out
                        q = (vertex(a, c), vertex(a, d), vertex(b, d), vertex(b, c))
                        emit((q[0], q[1], q[2]), inside_pt)
                        emit((q[0], q[2], q[3]), inside_pt)
    out = sys.stdout
    out.write("# bunny-like closed mesh, generated by assets/meshes/make_bunny.py %d (Pliant, procedural)\n" % n)
    for v in verts:
        out.write("v %.5f %.5f %.5f\n" % v)
    for t in tris:
        out.write("f %d %d %d\n" % t)


if __name__ == "__main__":
    main()
