#!/usr/bin/env python3
"""Draws the launcher icon (a wave under a low sun) into res/mipmap-*/ic_launcher.png.

Standard library only; run from anywhere: `python3 android/make_icon.py`. The PNGs are
committed, so the build never runs this.
"""
import math
import os
import struct
import zlib

DENSITIES = {"mdpi": 48, "hdpi": 72, "xhdpi": 96, "xxhdpi": 144, "xxxhdpi": 192}
SS = 4  # supersampling per axis


def mix(a, b, t):
    return tuple(x + (y - x) * t for x, y in zip(a, b))


def shade(u, v):
    """RGBA (0-1) at unit coordinates u, v (v down) of the icon."""
    # Rounded square mask (corner radius 0.2).
    r = 0.2
    dx = max(abs(u - 0.5) - (0.5 - r), 0.0)
    dy = max(abs(v - 0.5) - (0.5 - r), 0.0)
    if dx * dx + dy * dy > r * r:
        return (0.0, 0.0, 0.0, 0.0)
    sky = mix((0.98, 0.72, 0.45), (0.33, 0.60, 0.90), min(1.0, max(0.0, (0.62 - v) / 0.62)))
    # The sun, low over the horizon.
    if (u - 0.68) ** 2 + (v - 0.36) ** 2 < 0.11 ** 2:
        sky = (1.0, 0.93, 0.70)
    # A swell with a steeper crest (sum of two harmonics), and a foam line along it.
    crest = 0.60 - 0.07 * math.sin(2 * math.pi * (u * 1.15 + 0.1)) - 0.025 * math.sin(
        2 * math.pi * (u * 2.3 + 0.35)
    )
    if v < crest - 0.025:
        return sky + (1.0,)
    if v < crest:
        return (0.95, 0.98, 1.0, 1.0)
    depth = min(1.0, (v - crest) / 0.45)
    sea = mix((0.05, 0.45, 0.60), (0.02, 0.16, 0.32), depth)
    # A second, darker wave line lower down.
    crest2 = 0.80 - 0.03 * math.sin(2 * math.pi * (u * 1.7 + 0.6))
    if crest2 - 0.012 < v < crest2:
        sea = mix(sea, (0.55, 0.80, 0.90), 0.6)
    return sea + (1.0,)


def render(size):
    rows = []
    for y in range(size):
        row = bytearray([0])  # filter: none
        for x in range(size):
            acc = [0.0, 0.0, 0.0, 0.0]
            for sy in range(SS):
                for sx in range(SS):
                    c = shade((x + (sx + 0.5) / SS) / size, (y + (sy + 0.5) / SS) / size)
                    acc[0] += c[0] * c[3]
                    acc[1] += c[1] * c[3]
                    acc[2] += c[2] * c[3]
                    acc[3] += c[3]
            a = acc[3] / (SS * SS)
            rgb = [acc[i] / acc[3] if acc[3] > 0 else 0.0 for i in range(3)]
            row += bytes(round(255 * min(1.0, max(0.0, c))) for c in rgb + [a])
        rows.append(bytes(row))
    return png(size, size, b"".join(rows))


def png(w, h, raw):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)  # 8-bit RGBA
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", ihdr)
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )


def main():
    res = os.path.join(os.path.dirname(os.path.abspath(__file__)), "res")
    for name, size in DENSITIES.items():
        out = os.path.join(res, "mipmap-" + name)
        os.makedirs(out, exist_ok=True)
        path = os.path.join(out, "ic_launcher.png")
        with open(path, "wb") as f:
            f.write(render(size))
        print(path)


if __name__ == "__main__":
    main()
