#!/usr/bin/env python3
# tests/data/gz/make_gz.py - writes the gzip twins of the files here (png_gzip_twins):
#   room.pbrt.gz   one member, FNAME set (as gzip(1) writes it), of room-gz.pbrt
#                  (room.pbrt naming the .gz files)
#   light.pbrt.gz  two members (light.pbrt cut in two, each compressed alone)
#   box.ply.gz     one member with FEXTRA, FNAME, FCOMMENT and FHCRC all set
# and box.ply itself (a binary little-endian PLY: a box of 8 vertices, 12 triangles).
import struct, zlib

def member(data, name=None, extra=None, comment=None, hcrc=False, level=9):
    flg = (4 if extra is not None else 0) | (8 if name else 0) | (16 if comment else 0) | (2 if hcrc else 0)
    h = bytes([0x1F, 0x8B, 8, flg]) + struct.pack('<I', 0) + bytes([2, 3])
    if extra is not None: h += struct.pack('<H', len(extra)) + extra
    if name: h += name + b'\0'
    if comment: h += comment + b'\0'
    if hcrc: h += struct.pack('<H', zlib.crc32(h) & 0xFFFF)
    c = zlib.compressobj(level, zlib.DEFLATED, -15)
    body = c.compress(data) + c.flush()
    return h + body + struct.pack('<II', zlib.crc32(data), len(data) & 0xFFFFFFFF)

v = [(x, y, z) for x in (-1, 1) for y in (0, 1.5) for z in (-1, 1)]
faces = [(0,1,3),(0,3,2),(4,6,7),(4,7,5),(0,4,5),(0,5,1),(2,3,7),(2,7,6),(0,2,6),(0,6,4),(1,5,7),(1,7,3)]
ply = (b'ply\nformat binary_little_endian 1.0\ncomment a box for the gzip tests\n'
       b'element vertex 8\nproperty float x\nproperty float y\nproperty float z\n'
       b'element face 12\nproperty list uchar int vertex_indices\nend_header\n')
for p in v: ply += struct.pack('<3f', *p)
for f in faces: ply += struct.pack('<B3i', 3, *f)
open('box.ply', 'wb').write(ply)
open('box.ply.gz', 'wb').write(member(ply, name=b'box.ply', extra=b'AP\x04\x00spec',
                                       comment=b'a comment', hcrc=True))
light = open('light.pbrt', 'rb').read()
cut = len(light) // 2
open('light.pbrt.gz', 'wb').write(member(light[:cut], name=b'light.pbrt') + member(light[cut:], level=1))
room = open('room.pbrt', 'rb').read()
room = room.replace(b'"light.pbrt"', b'"light.pbrt.gz"').replace(b'"box.ply"', b'"box.ply.gz"')
open('room.pbrt.gz', 'wb').write(member(room, name=b'room.pbrt'))
