#!/usr/bin/env python3
"""Packs the MakeHuman body kit (CC0; base mesh, default skeleton, skin weights, macro targets)
into the simulator's compact binary (body_scan_driver/data/mesh_human/mesh_human.bin).

Kept: the `body` quads, the vertices they use, the vertices the skeleton's joints are defined by
(joint-helper cubes, a few others), every bone with its head and tail joints, the skin weights of
the body vertices, and the 84 macro targets restricted to the kept vertices (identical target
files stored once). Dropped: texture coordinates, helper geometry (tights, skirt, hair shells,
eyes, teeth), rotation planes, the weights of helper vertices.

Format (little-endian; str = u16 byte length + UTF-8 bytes):
  "BSMH" u32 version(1)
  u32 V; f32[V][3] base positions (decimetres, MakeHuman axes: +y up, face +z, left +x)
  u32 body vertices (the first ones; they are base.obj's 0..N-1 in order)
  u32 Q; u16[Q][4] body quads (counter-clockwise seen from outside)
  u32 J; J x (str name, u16 n, u16[n] vertices)      joint = mean of its vertices
  u32 B; B x (str name, str parent ('' = root), str head joint, str tail joint,
              u32 n, n x (u16 vertex, f32 weight))   raw weights, not yet normalized
  u32 T; T x (str name, i32 same_as, [if same_as < 0: u32 n, n x (u16 vertex, i16 dx, dy, dz)])
           offsets in 1/1000 decimetre (the files' own precision); same_as = an earlier target
           with identical offsets

Usage: pack_mesh_human.py KIT_DIR OUTPUT
"""
import json
import os
import struct
import sys


def read_obj(path):
    vertices, groups, group = [], {}, None
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == 'v':
                vertices.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == 'g':
                group = parts[1]
                groups.setdefault(group, [])
            elif parts[0] == 'f':
                groups[group].append([int(p.split('/')[0]) - 1 for p in parts[1:]])
    return vertices, groups


def read_target(path):
    entries = []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) != 4 or parts[0].startswith('#'):
                continue
            entries.append((int(parts[0]), *(round(float(x) * 1000) for x in parts[1:])))
    return entries


def pack_str(s):
    b = s.encode()
    return struct.pack('<H', len(b)) + b


def main(kit, output):
    vertices, groups = read_obj(os.path.join(kit, '3dobjs/base.obj'))
    quads = groups['body']
    body = sorted({i for q in quads for i in q})
    assert body == list(range(len(body))), 'body vertices must be 0..N-1'
    skeleton = json.load(open(os.path.join(kit, 'rigs/default.mhskel')))
    weights = json.load(open(os.path.join(kit, 'rigs/default_weights.mhw')))['weights']
    joint_vertices = sorted({i for vs in skeleton['joints'].values() for i in vs} - set(body))
    kept = body + joint_vertices
    new_index = {old: new for new, old in enumerate(kept)}
    assert len(kept) < 65536

    out = bytearray(b'BSMH' + struct.pack('<I', 1))
    out += struct.pack('<I', len(kept))
    for i in kept:
        out += struct.pack('<3f', *vertices[i])
    out += struct.pack('<I', len(body))
    out += struct.pack('<I', len(quads))
    for q in quads:
        out += struct.pack('<4H', *(new_index[i] for i in q))
    joints = skeleton['joints']
    out += struct.pack('<I', len(joints))
    for name in sorted(joints):
        out += pack_str(name) + struct.pack('<H', len(joints[name]))
        out += struct.pack('<%dH' % len(joints[name]), *(new_index[i] for i in joints[name]))
    bones = skeleton['bones']
    out += struct.pack('<I', len(bones))
    for name in sorted(bones):
        bone = bones[name]
        pairs = [(v, w) for v, w in weights.get(name, []) if v < len(body)]
        out += pack_str(name) + pack_str(bone['parent'] or '') + pack_str(bone['head'])
        out += pack_str(bone['tail']) + struct.pack('<I', len(pairs))
        for v, w in pairs:
            out += struct.pack('<Hf', v, w)
    target_dir = os.path.join(kit, 'targets/macrodetails')
    names = sorted(f[:-7] for f in os.listdir(target_dir) if f.endswith('.target'))
    names += sorted('height/' + f[:-7] for f in os.listdir(os.path.join(target_dir, 'height')))
    out += struct.pack('<I', len(names))
    seen = {}
    for index, name in enumerate(names):
        entries = tuple(e for e in read_target(os.path.join(target_dir, name + '.target'))
                        if e[0] in new_index and any(e[1:]))
        out += pack_str(name)
        if entries in seen:
            out += struct.pack('<i', seen[entries])
            continue
        seen[entries] = index
        out += struct.pack('<iI', -1, len(entries))
        for i, dx, dy, dz in entries:
            out += struct.pack('<H3h', new_index[i], dx, dy, dz)
    tmp = output + '.tmp'
    with open(tmp, 'wb') as f:
        f.write(out)
    os.replace(tmp, output)
    print('%s: %d bytes, %d vertices (%d body), %d quads, %d joints, %d bones, %d targets '
          '(%d stored)' % (output, len(out), len(kept), len(body), len(quads), len(joints),
                           len(bones), len(names), len(seen)))


if __name__ == '__main__':
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
