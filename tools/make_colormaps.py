#!/usr/bin/env python3
"""Generate silt's colormaps (assets/*.csv: 256 rows of r,g,b in [0, 1]).

Both maps are built in CIELAB so that lightness L* changes linearly along the map, which is what
makes a colormap perceptually ordered and readable in grey:
  - sequential: L* from 18 to 93 while the hue turns from blue-violet through teal and green to
    yellow, with chroma peaking in the middle (the recipe of viridis-like maps);
  - diverging: blue (L* 35) to white (L* 100) to red (L* 35), symmetric in L* and chroma, so
    that zero sits at the lightest point and equal magnitudes of opposite sign look equally strong.
Run: tools/make_colormaps.py (writes assets/sequential.csv and assets/diverging.csv).
"""
import math
import os


def lab_to_srgb(L, a, b):
    # CIELAB (D65) -> XYZ -> linear sRGB -> gamma-encoded sRGB, clipped to [0, 1].
    fy = (L + 16) / 116
    fx = fy + a / 500
    fz = fy - b / 200
    def finv(t):
        return t ** 3 if t ** 3 > 0.008856 else (t - 16 / 116) / 7.787
    X, Y, Z = 0.95047 * finv(fx), 1.0 * finv(fy), 1.08883 * finv(fz)
    r = 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z
    g = -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z
    bb = 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z
    def gamma(c):
        c = min(max(c, 0.0), 1.0)
        return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
    return gamma(r), gamma(g), gamma(bb)


def lch(L, C, h_deg):
    h = math.radians(h_deg)
    return lab_to_srgb(L, C * math.cos(h), C * math.sin(h))


def sequential(n=256):
    rows = []
    for i in range(n):
        t = i / (n - 1)
        L = 18 + 75 * t
        h = 300 - 205 * t              # blue-violet (300) -> teal (200) -> green (140) -> yellow (95)
        C = 38 + 30 * math.sin(math.pi * t) + 20 * t
        rows.append(lch(L, C, h))
    return rows


def diverging(n=256):
    rows = []
    for i in range(n):
        t = i / (n - 1)
        s = abs(2 * t - 1)             # 0 at the centre, 1 at the ends
        L = 100 - 65 * s
        C = 55 * s ** 0.8
        h = 260 if t < 0.5 else 25      # blue below zero, red above
        rows.append(lch(L, C, h))
    return rows


def write(path, rows, title):
    with open(path, "w") as f:
        f.write("# silt colormap: %s; 256 rows of r,g,b in [0, 1]; made by tools/make_colormaps.py\n" % title)
        for r, g, b in rows:
            f.write("%.6f,%.6f,%.6f\n" % (r, g, b))


if __name__ == "__main__":
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets")
    write(os.path.join(here, "sequential.csv"), sequential(), "sequential, lightness 18 to 93 (viridis-like)")
    write(os.path.join(here, "diverging.csv"), diverging(), "diverging blue-white-red, white at the centre")
