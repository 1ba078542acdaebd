#!/usr/bin/env python3
# tests/data/arealimg/make_images.py - writes the emission images of the area-light
# image tests (tests/test_arealimg.c, lamp.pbrt):
#   lamp.pfm   8 x 8: a colour gradient over the square (orange at the top left, blue
#              at the bottom right) with a bright white 2 x 2 spot in the top-right
#              quarter and a black one in the bottom-left quarter, so that a flip of
#              u or of v moves light between quadrants;
#   half.pfm   2 x 1: the left texel black, the right one white (1 1 1);
#   white.pfm  2 x 1: both texels white;
#   const.pfm  1 x 1: rgb (0.9 0.5 0.2), the colour of an "rgb L" it is compared with;
#   black.pfm  1 x 1: black, which no "float power" can scale (tests/test_lightpower.c).
import struct

def write(name, rows):
    h, w = len(rows), len(rows[0])
    with open(name, 'wb') as f:
        f.write(b'PF\n%d %d\n-1.0\n' % (w, h))
        for row in reversed(rows):       # PFM stores the bottom row first
            for px in row:
                f.write(struct.pack('<3f', *px))

n = 8
lamp = []
for y in range(n):                       # y = 0: the top row
    row = []
    for x in range(n):
        r, g, b = 1.5 - 1.2 * x / n, 0.4 + 0.4 * y / n, 0.2 + 1.6 * y / n * x / n
        if x in (5, 6) and y in (1, 2):
            r, g, b = 6.0, 6.0, 6.0
        if x in (1, 2) and y in (5, 6):
            r, g, b = 0.0, 0.0, 0.0
        row.append((r, g, b))
    lamp.append(row)
write('lamp.pfm', lamp)
write('half.pfm', [[(0.0, 0.0, 0.0), (1.0, 1.0, 1.0)]])
write('white.pfm', [[(1.0, 1.0, 1.0), (1.0, 1.0, 1.0)]])
write('const.pfm', [[(0.9, 0.5, 0.2)]])
write('black.pfm', [[(0.0, 0.0, 0.0)]])
