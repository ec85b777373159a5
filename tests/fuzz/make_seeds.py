#!/usr/bin/env python3
"""Writes the small hand-made seeds of the fuzz corpora (tests/fuzz/corpus/<harness>/).

Run once from anywhere; the files are committed. The .bt, .ot and .fcm seeds are not written
here: they were made with the fvx binary (integrate, capmap build) and are committed as
they are. scripts/fuzz.sh adds the project's data/ files and, when
FVX_REAL_DATA is set, small real files to the working corpus at run time.
"""
import os
import struct
import zlib

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
POINTS = [(0.1 * i, -0.05 * i, 1.0 + 0.02 * i) for i in range(6)]


def put(harness, name, data):
    os.makedirs(os.path.join(HERE, harness), exist_ok=True)
    with open(os.path.join(HERE, harness, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def pcd_header(data, width, height, viewpoint="0 0 0 1 0 0 0", fields="x y z"):
    n = len(fields.split())
    return (f"# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {fields}\n"
            f"SIZE {' '.join(['4'] * n)}\nTYPE {' '.join(['F'] * n)}\nCOUNT {' '.join(['1'] * n)}\n"
            f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT {viewpoint}\nPOINTS {width * height}\n"
            f"DATA {data}\n")


def lzf_literals(raw):
    """LZF as literal runs only (control byte = run length - 1): valid, uncompressed."""
    out = b""
    for i in range(0, len(raw), 32):
        chunk = raw[i:i + 32]
        out += bytes([len(chunk) - 1]) + chunk
    return out


def pcd_seeds():
    ascii_rows = "".join(f"{x} {y} {z}\n" for x, y, z in POINTS)
    put("fuzz_pcd", "ascii.pcd", pcd_header("ascii", 6, 1) + ascii_rows)
    put("fuzz_pcd", "ascii-organised-nan.pcd",
        pcd_header("ascii", 3, 2, "0.5 0 1 0.7071 0 0.7071 0") + ascii_rows.replace("0.0 -0.0 1.0", "nan nan nan"))
    binary = b"".join(struct.pack("<fff", *p) for p in POINTS)
    put("fuzz_pcd", "binary.pcd", pcd_header("binary", 6, 1).encode() + binary)
    soa = b"".join(struct.pack("<6f", *[p[k] for p in POINTS]) for k in range(3))
    packed = lzf_literals(soa)
    put("fuzz_pcd", "binary-compressed.pcd",
        pcd_header("binary_compressed", 6, 1).encode() + struct.pack("<II", len(packed), len(soa)) + packed)
    rgb = "".join(f"{x} {y} {z} 4.2108e+06\n" for x, y, z in POINTS)
    put("fuzz_pcd", "ascii-rgb.pcd", pcd_header("ascii", 6, 1, fields="x y z rgb") + rgb)


def ply_seeds():
    head = "ply\nformat {} 1.0\ncomment fvx fuzz seed\nelement vertex 6\nproperty float x\n" \
           "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    put("fuzz_ply", "ascii.ply", head.format("ascii") + "".join(f"{x} {y} {z}\n" for x, y, z in POINTS) + "3 0 1 2\n")
    for order, tag in (("<", "binary_little_endian"), (">", "binary_big_endian")):
        body = b"".join(struct.pack(order + "fff", *p) for p in POINTS) + struct.pack(order + "Biii", 3, 0, 1, 2)
        put("fuzz_ply", tag + ".ply", head.format(tag).encode() + body)


DEPTH = [[(1000 + 37 * r + 11 * c) if (r + c) % 5 else 0 for c in range(8)] for r in range(6)]


def png16(rows):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    raw = b"".join(b"\0" + b"".join(struct.pack(">H", v) for v in row) for row in rows)
    ihdr = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 16, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def tiff16(rows):
    h, w = len(rows), len(rows[0])
    pixels = b"".join(struct.pack("<H", v) for row in rows for v in row)
    tags = [(256, 3, 1, w), (257, 3, 1, h), (258, 3, 1, 16), (259, 3, 1, 1), (262, 3, 1, 1),
            (273, 4, 1, 8), (277, 3, 1, 1), (278, 3, 1, h), (279, 4, 1, len(pixels))]
    ifd = struct.pack("<H", len(tags)) + b"".join(struct.pack("<HHII", *t) for t in tags) + struct.pack("<I", 0)
    return b"II*\0" + struct.pack("<I", 8 + len(pixels)) + pixels + ifd


def depth_seeds():
    put("fuzz_depth_image", "depth.png", png16(DEPTH))
    pgm = b"P5\n8 6\n65535\n" + b"".join(struct.pack(">H", v) for row in DEPTH for v in row)
    put("fuzz_depth_image", "depth.pgm", pgm)
    put("fuzz_depth_image", "depth.tiff", tiff16(DEPTH))


def trajectory_seeds():
    put("fuzz_trajectory", "tum.txt", "# timestamp tx ty tz qx qy qz qw\n"
        "1305031102.175304 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n"
        "1305031102.211214 1.3303 0.6256 1.6464 0.6579 0.6161 -0.2932 -0.3189\n")
    put("fuzz_trajectory", "tum-no-stamp.txt", "0 0 1 0 0 0 1\n0.1 0 1 0 0 0.0998 0.995\n")
    put("fuzz_trajectory", "redwood.log", "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
        "1 1 2\n0.999 -0.0436 0 0.1\n0.0436 0.999 0 0\n0 0 1 0.02\n0 0 0 1\n")


def json_seeds():
    put("fuzz_json", "intrinsics.json", '{"width": 640, "height": 480, "fx": 525.0, "fy": 525.0, '
        '"cx": 319.5, "cy": 239.5, "depth_scale": 1000}\n')
    put("fuzz_json", "sensor.json", '{"width": 64, "height": 48, "fx": 52.5, "fy": 52.5, "cx": 31.5, '
        '"cy": 23.5, "depth_scale": 5000, "depth_min_m": 0.5, "depth_max_m": 4.0}\n')


URDF = """<?xml version="1.0"?>
<robot name="seed">
  <link name="base_link"/>
  <link name="upper"/>
  <link name="camera"/>
  <joint name="pan" type="revolute">
    <parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.9" upper="2.9" effort="1" velocity="1"/>
  </joint>
  <joint name="lift" type="prismatic">
    <parent link="upper"/><child link="camera"/>
    <origin xyz="0.2 0 0" rpy="0 1.5708 0"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.3" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def urdf_seeds():
    put("fuzz_urdf", "small.txt", "base_link camera\n" + URDF)
    put("fuzz_urdf", "cycle.txt", "base_link camera\n" + URDF.replace(
        "</robot>", '  <joint name="back" type="fixed"><parent link="camera"/><child link="upper"/></joint>\n</robot>'))


if __name__ == "__main__":
    pcd_seeds()
    ply_seeds()
    depth_seeds()
    trajectory_seeds()
    json_seeds()
    urdf_seeds()
