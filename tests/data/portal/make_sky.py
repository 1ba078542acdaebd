#!/usr/bin/env python3
# tests/data/portal/make_sky.py - writes sky.pfm, the 32 x 32 equal-area map of
# room-map.pbrt: a smooth colour gradient over the square and a 2 x 2 texel "sun"
# of 40 at (0, 0.6, 0.8) in the light's frame (world (0, 0.8, -0.6) in
# room-map.pbrt: its light falls through the window onto the far wall).
import struct
n = 32
rows = []
for y in range(n):                       # y = 0: the top row
    row = []
    for x in range(n):
        r, g, b = 0.2 + 0.8 * x / n, 0.3 + 0.6 * y / n, 1.0 - 0.5 * x / n
        if x in (15, 16) and y in (23, 24):
            r, g, b = 40.0, 36.0, 30.0
        row.append((r, g, b))
    rows.append(row)
with open('sky.pfm', 'wb') as f:
    f.write(b'PF\n%d %d\n-1.0\n' % (n, n))
    for row in reversed(rows):           # PFM stores the bottom row first
        for px in row:
            f.write(struct.pack('<3f', *px))
