#!/usr/bin/python3
"""Regenerates wavepath's synthetic assets (run from the repository root).

scenes/assets/sky.hdr, tests/data/features/sky.hdr: equirectangular skies with a
sun (Radiance RGBE, uncompressed scanlines); scenes/assets/test-card.png and
tests/data/features/tiles.png: sRGB test images; tests/data/features/uv-sphere.obj:
a UV sphere with vertex normals and texture coordinates. Standard library only.
"""
import math
import struct
import zlib


def write_png(path, w, h, pixels):
    raw = b"".join(b"\x00" + bytes(sum((pixels[y * w + x] for x in range(w)), ())) for y in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def rgbe(r, g, b):
    v = max(r, g, b)
    if v < 1e-32:
        return bytes([0, 0, 0, 0])
    m, e = math.frexp(v)
    scale = m * 256.0 / v
    return bytes([int(r * scale), int(g * scale), int(b * scale), e + 128])


def write_hdr(path, w, h, radiance):
    out = bytearray(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
    for y in range(h):
        for x in range(w):
            out += rgbe(*radiance((x + 0.5) / w, (y + 0.5) / h))
    with open(path, "wb") as f:
        f.write(bytes(out))


def sky(u, v, sun_u=0.3, sun_v=0.25, sun_size=0.035, sun=60.0):
    """Sky gradient above the horizon, ground below, a disc sun. (u, v): image
    coordinates, v = 0 at the top row (straight up), as wavepath maps them."""
    theta, phi = v * math.pi, (u - 0.5) * 2 * math.pi
    d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
    st, sp = sun_v * math.pi, (sun_u - 0.5) * 2 * math.pi
    s = (math.sin(st) * math.sin(sp), math.cos(st), -math.sin(st) * math.cos(sp))
    c = [0.35 + 0.3 * (1 - d[1]), 0.5 + 0.25 * (1 - d[1]), 0.9] if d[1] > 0 else [0.25, 0.22, 0.2]
    if sum(a * b for a, b in zip(d, s)) > math.cos(sun_size * math.pi):
        c = [sun, sun * 0.9, sun * 0.75]
    return c


def test_card(w):
    pixels = []
    for y in range(w):
        for x in range(w):
            u, v = x / w, y / w
            c = [(230, 90, 60), (70, 160, 220), (240, 200, 70), (90, 190, 110)][(u >= 0.5) + 2 * (v >= 0.5)]
            if x % 16 == 0 or y % 16 == 0:
                c = (250, 250, 250)
            if (u - 0.5) ** 2 + (v - 0.5) ** 2 < 0.04:
                c = (40, 40, 50)
            pixels.append(c)
    return pixels


def uv_sphere(nu=12, nv=8):
    lines = ["# UV sphere, %d x %d, with vn and vt (scripts/make-assets.py)" % (nu, nv)]
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu + 1):
            ph = 2 * math.pi * i / nu
            x, y, z = math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)
            lines += ["v %.6f %.6f %.6f" % (x, y, z), "vn %.6f %.6f %.6f" % (x, y, z), "vt %.6f %.6f" % (i / nu, 1 - j / nv)]

    def idx(i, j):
        return j * (nu + 1) + i + 1

    for j in range(nv):
        for i in range(nu):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            if j != 0:
                lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, c, c, c, b, b, b))
            if j != nv - 1:
                lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, d, d, d, c, c, c))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    write_hdr("scenes/assets/sky.hdr", 256, 128, sky)
    write_hdr("tests/data/features/sky.hdr", 32, 16, lambda u, v: sky(u, v, sun_size=0.08, sun=12.0))
    write_png("scenes/assets/test-card.png", 128, 128, test_card(128))
    tiles = [((x * 80 + 20) % 256, (y * 70 + 30) % 256, ((x + y) * 40 + 60) % 256) for y in range(4) for x in range(4)]
    write_png("tests/data/features/tiles.png", 4, 4, tiles)
    with open("tests/data/features/uv-sphere.obj", "w") as f:
        f.write(uv_sphere())
